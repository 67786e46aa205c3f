"""``zmpkit balance`` end to end on the virtual TEO (a few targets), and its CLI contracts."""

from __future__ import annotations

import csv
import pickle
import re
from dataclasses import replace
from html import escape as html_escape
from pathlib import Path

import imageio_ffmpeg
import pytest
from hypothesis import given
from hypothesis import strategies as st

from helpers.gl import skip_without_gl
from zmpkit.analysis.table1 import TABLE1_COLUMNS
from zmpkit.cli import main
from zmpkit.identify import BalanceParams
from zmpkit.pipelines.balance import (
    MIN_CHOSEN_TARGETS,
    BalanceConfig,
    fit_targets_of,
    run_balance,
    step_experiment,
)
from zmpkit.pipelines.balance_checks import balance_checks
from zmpkit.pipelines.balance_files import write_balance
from zmpkit.pipelines.balance_video import BALANCE_VIDEO, STEP_TRIAL_AFTER_S

CONFIG = BalanceConfig(
    planes=("sagittal",),
    targets_m=(0.0, 0.02, 0.04, 0.05, 0.06, 0.08),
    fit_targets_m=(0.0, 0.02, 0.04, 0.06, 0.08),
    hold_s=12.0,
)


@pytest.fixture(scope="module")
def balance_run(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("balance")
    result = run_balance(CONFIG, out, echo=lambda _: None)
    return out, result, write_balance(result, out)


@pytest.mark.slow
def test_dlipm_error_is_below_lipm_error(balance_run) -> None:
    _, result, _ = balance_run
    rows = [r for r in result.planes["sagittal"].rows if r.zmp_ref > 0]
    for row in rows:
        assert row.lipm.error_pct is not None
        assert row.dlipm.error_pct is not None
        assert abs(row.dlipm.error_pct) < abs(row.lipm.error_pct)
    validation = [r for r in rows if not r.fitted_on]
    assert [r.zmp_ref for r in validation] == [0.05]  # the schedule between fitted points


@pytest.mark.slow
def test_artefacts_follow_their_contracts(balance_run) -> None:
    out, _, artifacts = balance_run
    with artifacts.table1.open() as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames or ()) == TABLE1_COLUMNS
        assert [row["zmp_ref"] for row in reader] == ["0", "0.02", "0.04", "0.05", "0.06", "0.08"]
    params = BalanceParams.from_yaml(out / "params_sagittal.yaml")
    assert params.mass == pytest.approx(62.6)
    html = artifacts.report.read_text()
    assert artifacts.report.name == "report.html"
    assert 'id="verdict"' in html
    assert "Table 1 (paper A)" in html
    # every empty cell of Table 1 points to a note that says why it is empty
    marks = set(re.findall(r"– \((\d+)\)", html))
    assert marks
    assert all(f"({k}) " in html for k in marks)
    assert all(p.exists() for p in artifacts.figures)


@pytest.mark.slow
def test_rerun_resumes_every_sweep(balance_run) -> None:
    out, first, _ = balance_run
    again = run_balance(CONFIG, out, echo=lambda _: None)
    old, new = first.planes["sagittal"].rows, again.planes["sagittal"].rows
    assert [r.dlipm.zmp_measured for r in new] == [r.dlipm.zmp_measured for r in old]


@pytest.mark.slow
def test_controller_factory_pickles_for_worker_processes(balance_run) -> None:
    _, result, _ = balance_run
    factory = result.planes["sagittal"].factories["dlipm"]
    clone = pickle.loads(pickle.dumps(factory))
    a, b = factory(), clone()
    a.set_target(0.05)
    b.set_target(0.05)
    assert [a.step() for _ in range(50)] == [b.step() for _ in range(50)]


@pytest.mark.slow
def test_identify_balance_command_on_a_recorded_dataset(
    balance_run, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, _, _ = balance_run
    dataset = out / "datasets" / "sagittal_lipm"
    assert main(["identify", "balance", str(dataset), "--out", str(tmp_path)]) == 0
    assert "x_ft = " in capsys.readouterr().out
    assert BalanceParams.from_yaml(tmp_path / "params.yaml").plane("sagittal") is not None


def test_balance_bad_effects_is_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["balance", "--effects", "X", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "X" in err


def test_fit_targets_must_be_run() -> None:
    from zmpkit.errors import ParameterError

    with pytest.raises(ParameterError, match=r"fit target 0.07 m is not among the targets"):
        BalanceConfig(targets_m=(0.0, 0.05), fit_targets_m=(0.0, 0.07))


@pytest.mark.slow
def test_nothing_is_tuned_to_the_shipped_truth(tmp_path: Path) -> None:
    """Another robot (less softening, 3x backlash, a larger F-T offset, heavier payload):
    the same pipeline identifies it and the DLIPM still beats the LIPM at every target."""
    from zmpkit.robots.teo import truth as teo_truth

    text = Path(teo_truth.__file__).with_name("data").joinpath("truth.yaml").read_text()
    other = (
        text.replace("softening_torque: 0.65", "softening_torque: 1.2")
        .replace("backlash: 0.0003 ", "backlash: 0.0010 ")
        .replace("right: [3.0, -2.0, 3.0,", "right: [3.0, -2.0, 8.0,")
        .replace("mass_kg: 6.66 ", "mass_kg: 8.00 ")
    )
    assert other.count("1.2, softening_torque_range") == 2  # the edits took
    (tmp_path / "truth.yaml").write_text(other)
    config = BalanceConfig(
        planes=("sagittal",),
        targets_m=CONFIG.targets_m,
        fit_targets_m=CONFIG.fit_targets_m,
        hold_s=12.0,
        truth=str(tmp_path / "truth.yaml"),
    )
    result = run_balance(config, tmp_path / "out", echo=lambda _: None)
    for row in result.planes["sagittal"].rows:
        if row.zmp_ref > 0:
            assert abs(row.dlipm.error_pct) < abs(row.lipm.error_pct)


@pytest.mark.slow
def test_report_and_artifacts_carry_the_verdict(balance_run) -> None:
    _, _, artifacts = balance_run
    verdict = artifacts.verdicts["sagittal"]
    assert [b.name for b in verdict.bars] == ["far error ratio", "mean error ratio"]
    assert all(b.state in ("met", "missed", "undefined") for b in verdict.bars)
    assert artifacts.met == verdict.met
    report = artifacts.report.read_text()
    assert 'id="verdict"' in report
    checks = balance_checks(balance_run[1], artifacts.verdicts)
    bars = [c for c in checks if c.status != "info"]
    assert [c.status for c in bars] == [b.state for b in verdict.bars]
    assert "a fitted target" in bars[0].name or "a held out target" in bars[0].name
    assert all(html_escape(c.detail) in report for c in checks)
    assert "fitted range (measured ZMP):" in report


@pytest.mark.parametrize(
    ("met", "strict", "code", "says"),
    [
        (True, True, 0, "every bar met: exit 0"),
        (False, False, 0, "exit 0 (--strict exits 1)"),
        (False, True, 1, "--strict: a bar is missed or undefined: exit 1"),
    ],
)
def test_only_strict_turns_a_missed_bar_into_a_failing_exit(
    met: bool, strict: bool, code: int, says: str, capsys: pytest.CaptureFixture[str]
) -> None:
    from zmpkit.cli.balance import _exit_code

    assert _exit_code(met, strict) == code
    assert says in capsys.readouterr().out


@pytest.mark.slow
def test_balance_video_films_the_dlipm_at_the_largest_target(balance_run, tmp_path: Path) -> None:
    skip_without_gl()
    _, result, _ = balance_run
    filmed = replace(result, config=replace(CONFIG, video=True))
    artifacts = write_balance(filmed, tmp_path)
    assert artifacts.videos == (tmp_path / "step_trial.mp4",)
    reader = imageio_ffmpeg.read_frames(str(tmp_path / "step_trial.mp4"))
    assert next(reader)["size"] == (BALANCE_VIDEO.width_px, BALANCE_VIDEO.height_px)
    shown_s = step_experiment(CONFIG, "sagittal").startup_window_s + STEP_TRIAL_AFTER_S
    assert sum(1 for _ in reader) == pytest.approx(shown_s * BALANCE_VIDEO.fps + 1, abs=1)
    assert '<video controls loop muted playsinline preload="metadata" src="step_trial.mp4">' in (
        artifacts.report.read_text()
    )


@given(
    st.lists(st.integers(0, 200), min_size=MIN_CHOSEN_TARGETS, max_size=30, unique=True).map(
        lambda mm: tuple(v / 1000.0 for v in mm)
    )
)
def test_chosen_targets_fit_on_every_other_one_and_the_largest(targets: tuple[float, ...]) -> None:
    fit = fit_targets_of(targets)
    ordered = sorted(targets)
    assert set(fit) <= set(ordered)
    assert max(fit) == ordered[-1]  # the schedule spans them all
    assert min(fit) == ordered[0]
    assert len(fit) >= 3  # the error model's fewest points
    assert len(ordered) - len(fit) >= 1  # something left to validate on
    assert fit_targets_of(tuple(reversed(targets))) == fit  # order does not matter


@pytest.mark.parametrize(
    ("targets", "message"),
    [
        ("0,0.02,0.04", r"--targets needs at least 4 distinct targets .*got 3: 0, 0\.02, 0\.04 m"),
        ("0:0.5:0.1", r"ZMP target 0\.2 m lies outside teo's support polygon in the sagittal"),
        ("0,nan,1,2", r"--targets expects START:STOP:STEP in m"),
    ],
)
def test_balance_bad_targets_are_one_line_exit_2(
    targets: str, message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "never"
    assert main(["balance", "--robot", "teo", "--targets", targets, "--out", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert re.search(message, line), line
    assert not out.exists()  # refused before any work


@pytest.mark.slow
def test_a_failed_plane_keeps_the_finished_ones_report(
    balance_run, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    """The frontal plane's identification fails; the sagittal plane (the module's run) is
    reported, the frontal one's bars are undefined and say why, and no bar counts as met."""
    import zmpkit.pipelines.balance as balance_module
    from zmpkit.errors import ModelError

    _, finished, _ = balance_run
    why = "the error model has a negative slope: the robot does not lean as commanded"

    def run_plane(config, plane, out, progress):
        if plane == "frontal":
            raise ModelError(why)
        return finished.planes[plane]

    monkeypatch.setattr(balance_module, "_run_plane", run_plane)
    said: list[str] = []
    result = run_balance(
        replace(CONFIG, planes=("sagittal", "frontal")), tmp_path, echo=said.append
    )
    assert list(result.planes) == ["sagittal"]
    assert result.failed_planes == {"frontal": why}
    assert f"frontal plane failed: {why}" in said
    artifacts = write_balance(result, tmp_path)
    assert not artifacts.met
    html = artifacts.report.read_text(encoding="utf-8")
    assert "frontal: paper A" in html
    assert f"the plane failed: {why}" in html
    assert (tmp_path / "table1.csv").read_text(encoding="utf-8").count("sagittal") >= 1


def test_when_every_plane_fails_the_first_error_is_raised(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    import zmpkit.pipelines.balance as balance_module
    from zmpkit.errors import ModelError

    def run_plane(config, plane, out, progress):
        raise ModelError(f"{plane}: no error model")

    monkeypatch.setattr(balance_module, "_run_plane", run_plane)
    with pytest.raises(ModelError, match="sagittal: no error model"):
        run_balance(replace(CONFIG, planes=("sagittal", "frontal")), tmp_path, echo=lambda _: None)
