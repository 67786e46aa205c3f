"""Two fits compared parameter by parameter against their resolutions (identify compare)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.cli.app import main
from zmpkit.errors import InputFileError
from zmpkit.simfit.fit_agreement import compare_fits


def _fit(
    folder: Path,
    values: dict[str, tuple[float, float | None, bool]],
    robot: str = "nao",
) -> Path:
    """A fit's folder: per parameter (value, resolution [%] or None, identifiable)."""
    folder.mkdir(parents=True, exist_ok=True)
    doc = {
        "robot": robot,
        "effects": "M,G",
        "cost": 0.001,
        "parameters": {
            name: {"value": v, "unit": "-", "identifiable": ok, "resolution_pct": r}
            for name, (v, r, ok) in values.items()
        },
    }
    (folder / "fitted_parameters.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    return folder


def test_a_difference_within_the_larger_resolution_agrees(tmp_path: Path) -> None:
    a = _fit(tmp_path / "a", {"k": (100.0, 3.0, True), "g": (2.0, 1.0, True)})
    b = _fit(tmp_path / "b", {"k": (102.0, 1.0, True), "g": (1.97, 2.0, True)})
    result = compare_fits(a, b)
    k, g = result.parameters
    assert k.difference == pytest.approx(0.02)
    assert k.tolerance == pytest.approx(0.03)
    assert g.difference == pytest.approx(-0.015)
    assert g.tolerance == pytest.approx(0.02)
    assert k.agree
    assert g.agree
    assert result.agree


def test_a_difference_beyond_both_resolutions_differs(tmp_path: Path) -> None:
    a = _fit(tmp_path / "a", {"k": (100.0, 3.0, True), "g": (2.0, 1.0, True)})
    b = _fit(tmp_path / "b", {"k": (104.0, 1.0, True), "g": (2.0, 1.0, True)})
    result = compare_fits(a, b)
    assert [p.agree for p in result.parameters] == [False, True]
    assert not result.agree


def test_a_parameter_not_identifiable_in_either_fit_is_not_judged(tmp_path: Path) -> None:
    a = _fit(tmp_path / "a", {"k": (100.0, 3.0, True), "c": (0.01, None, False)})
    b = _fit(tmp_path / "b", {"k": (100.5, 3.0, True), "c": (0.03, 50.0, True)})
    k, c = compare_fits(a, b).parameters
    assert k.agree
    assert c.agree is None
    assert not c.judged
    assert c.tolerance == math.inf  # no resolution: the cost never rose
    assert compare_fits(a, b).agree


def test_zero_values_compare_without_dividing_by_zero(tmp_path: Path) -> None:
    a = _fit(tmp_path / "a", {"offset": (0.0, 5.0, True)})
    same = _fit(tmp_path / "b", {"offset": (0.0, 5.0, True)})
    other = _fit(tmp_path / "c", {"offset": (0.1, 5.0, True)})
    assert compare_fits(a, same).parameters[0].difference == 0.0
    assert compare_fits(a, other).parameters[0].difference == math.inf
    assert not compare_fits(a, other).agree


@settings(max_examples=50, deadline=None)
@given(
    values=st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=1, max_size=5),
    resolution=st.floats(0.0, 100.0),
    scale=st.floats(1e-3, 1e3),
)
def test_a_fit_agrees_with_itself_and_scaling_keeps_the_differences(
    tmp_path_factory: pytest.TempPathFactory, values: list[float], resolution: float, scale: float
) -> None:
    root = tmp_path_factory.mktemp("fits")
    a = {f"p{i}": (v, resolution, True) for i, v in enumerate(values)}
    b = {f"p{i}": (v * 1.01 + 0.5, resolution, True) for i, v in enumerate(values)}
    fit_a, fit_b = _fit(root / "a", a), _fit(root / "b", b)
    assert compare_fits(fit_a, fit_a).agree
    scaled_a = _fit(root / "sa", {k: (v * scale, r, ok) for k, (v, r, ok) in a.items()})
    scaled_b = _fit(root / "sb", {k: (v * scale, r, ok) for k, (v, r, ok) in b.items()})
    for p, q in zip(
        compare_fits(fit_a, fit_b).parameters,
        compare_fits(scaled_a, scaled_b).parameters,
        strict=True,
    ):
        if math.isfinite(p.difference):
            assert q.difference == pytest.approx(p.difference, rel=1e-9, abs=1e-12)
            assert q.agree == p.agree or abs(abs(p.difference) - p.tolerance) < 1e-9


def test_fits_of_other_robots_or_parameters_are_refused(tmp_path: Path) -> None:
    a = _fit(tmp_path / "a", {"k": (1.0, 1.0, True)})
    with pytest.raises(InputFileError, match="robot 'teo', but the first fit is of 'nao'"):
        compare_fits(a, _fit(tmp_path / "b", {"k": (1.0, 1.0, True)}, robot="teo"))
    with pytest.raises(InputFileError, match="same --effects"):
        compare_fits(a, _fit(tmp_path / "c", {"g": (1.0, 1.0, True)}))


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (None, "no fitted_parameters.yaml here"),
        ("robot: [unclosed", "line 1: invalid YAML"),
        ("just text", "expected a mapping at the top level"),
        ("parameters: {}", "no fitted parameters"),
        ("parameters: {k: {value: .nan, identifiable: true}}", "value: expected a finite"),
        (
            "parameters: {k: {value: 1, identifiable: true, resolution_pct: -1}}",
            "resolution_pct: expected a number >= 0",
        ),
        ("parameters: {k: {value: 1, identifiable: maybe}}", "identifiable: expected true"),
    ],
)
def test_bad_fit_files_get_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str | None, message: str
) -> None:
    good = _fit(tmp_path / "good", {"k": (1.0, 1.0, True)})
    bad = tmp_path / "bad"
    bad.mkdir()
    if text is not None:
        (bad / "fitted_parameters.yaml").write_text(text)
    assert main(["identify", "compare", str(good), str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "Traceback" not in err
    assert message in err
    assert str(bad) in err


def test_the_command_exits_0_when_the_fits_agree_and_1_when_not(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    a = _fit(tmp_path / "a", {"gear_stiffness": (1000.0, 2.0, True)})
    near = _fit(tmp_path / "b", {"gear_stiffness": (1010.0, 2.0, True)})
    far = _fit(tmp_path / "c", {"gear_stiffness": (1100.0, 2.0, True)})
    assert main(["identify", "compare", str(a), str(near / "fitted_parameters.yaml")]) == 0
    assert "agree in every identifiable parameter" in capsys.readouterr().out
    assert main(["identify", "compare", str(a), str(far)]) == 1
    out = capsys.readouterr().out
    assert "+10.00%" in out
    assert "the fits differ in gear_stiffness" in out


def test_the_marginal_resolution_is_the_tolerance_when_a_fit_has_it(tmp_path: Path) -> None:
    """A fit written with the marginal resolution (the others free) is judged on it, not on
    the profile's narrower one; a null marginal means the cost never rose visibly."""
    a = _fit(tmp_path / "a", {"k": (100.0, 1.0, True), "g": (2.0, 1.0, True)})
    b = _fit(tmp_path / "b", {"k": (104.0, 1.0, True), "g": (2.0, 1.0, True)})
    doc = yaml.safe_load((a / "fitted_parameters.yaml").read_text())
    doc["parameters"]["k"]["marginal_resolution_pct"] = 5.0
    doc["parameters"]["g"]["marginal_resolution_pct"] = None
    (a / "fitted_parameters.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    k, g = compare_fits(a, b).parameters
    assert k.tolerance == pytest.approx(0.05)  # the profile's 1 % would have failed +4 %
    assert k.agree
    assert g.tolerance == math.inf
