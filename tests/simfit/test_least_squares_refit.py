"""The cost as residuals, and the Gauss–Newton refinement built on them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.robots.fit_parameter import fit_parameter
from zmpkit.simfit.cost import FAILED_COST, CostWeights, experiment_cost
from zmpkit.simfit.cost_residuals import experiment_residuals, stacked_residuals
from zmpkit.simfit.least_squares_refit import refine_fit
from zmpkit.simfit.recorded import RecordedSignals

JOINTS = ("a", "b", "c")


def _random_signals(rng: np.random.Generator, n: int, gaps: float) -> RecordedSignals:
    t = np.arange(n) * 0.01
    cmd = 0.1 * np.sin(np.outer(t, [1.0, 2.0, 3.0]))
    meas = cmd + 0.01 * rng.standard_normal(cmd.shape)
    zmp = np.column_stack([0.05 * t + 0.01 * np.sin(7 * t), 0.02 * np.sin(3 * t)])
    zmp = zmp + 0.002 * rng.standard_normal(zmp.shape)
    zmp[rng.random(n) < gaps] = np.nan
    tilt = 0.01 * np.sin(2 * np.pi * 2 * t) + 0.001 * rng.standard_normal(n)
    load = 25.0 + 20.0 * np.sin(2 * np.pi * t)
    force = np.column_stack([load, 50.0 - load]) + rng.standard_normal((n, 2))
    force[rng.random(n) < gaps / 3] = np.nan  # a sensor that dropped out
    return RecordedSignals(t, JOINTS, cmd, meas, zmp, tilt, force)


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    gaps=st.floats(0.0, 0.3),
    keep=st.booleans(),
    w=st.tuples(*(st.floats(0.0, 3.0) for _ in range(4))),
)
def test_the_squared_residual_norm_is_the_cost(seed: int, gaps: float, keep: bool, w) -> None:
    rng = np.random.default_rng(seed)
    recorded, simulated = _random_signals(rng, 300, gaps), _random_signals(rng, 300, gaps)
    weights = CostWeights(*w)
    r = experiment_residuals(recorded, simulated, weights, keep)
    assert r is not None
    cost = experiment_cost(recorded, simulated, keep).total(weights)
    assert float(r @ r) == pytest.approx(cost, rel=1e-9, abs=1e-15)
    # the vector's length does not depend on the candidate: a Jacobian is defined
    other = _random_signals(rng, 300, 0.5)
    r2 = experiment_residuals(recorded, other, weights, keep)
    assert r2 is not None
    assert r2.shape == r.shape


def test_a_rollout_that_fell_has_no_residuals_and_the_stack_is_the_mean() -> None:
    rng = np.random.default_rng(0)
    rec = _random_signals(rng, 200, 0.0)
    assert experiment_residuals(rec, rec.head(150), CostWeights()) is None
    a = experiment_residuals(rec, _random_signals(rng, 200, 0.0), CostWeights())
    b = experiment_residuals(rec, _random_signals(rng, 200, 0.0), CostWeights())
    assert a is not None
    assert b is not None
    stacked = stacked_residuals([a, b])
    assert stacked is not None
    assert float(stacked @ stacked) == pytest.approx(0.5 * (a @ a + b @ b))
    assert stacked_residuals([a, None]) is None


class _Problem:
    """A stand-in with the two things :func:`refine_fit` reads: parameters and bounds."""

    def __init__(self) -> None:
        self.parameters = (
            fit_parameter("M", "k", "k", 2.0, (0.5, 8.0), "-"),
            fit_parameter("M", "b", "b", 0.0, (-1.0, 1.0), "-", False),
        )


def _model(values: np.ndarray, t: np.ndarray) -> np.ndarray:
    return np.exp(-values[0] * t) + values[1] * t


def test_refinement_recovers_a_nonlinear_least_squares_truth() -> None:
    """Against a closed form: data made by a known model, noise-free, is fitted exactly."""
    t = np.linspace(0.0, 2.0, 50)
    truth = np.array([3.3, -0.4])
    data = _model(truth, t)
    calls = []

    def residuals(candidates):
        calls.append(len(candidates))
        return [_model(np.asarray(c), t) - data for c in candidates]

    out = refine_fit(_Problem(), [2.0, 0.0], residuals)  # type: ignore[arg-type]
    assert out.improved
    np.testing.assert_allclose(out.values, truth, rtol=2e-3, atol=2e-3)
    assert out.cost < 1e-6 * out.start_cost
    assert out.jacobian.shape == (t.size, 2)
    # one candidate per trial point, the Jacobian's columns as one batch of n
    assert set(calls) <= {1, 2}
    assert 2 in calls
    assert out.rollouts == sum(calls)


def test_refinement_backs_away_from_a_fall_and_stays_in_bounds() -> None:
    t = np.linspace(0.0, 2.0, 50)
    truth = np.array([6.0, 0.9])
    data = _model(truth, t)

    def residuals(candidates):
        # candidates with k above 4 "fall": no residuals
        return [None if c[0] > 4.0 else _model(np.asarray(c), t) - data for c in candidates]

    out = refine_fit(_Problem(), [2.0, 0.0], residuals)  # type: ignore[arg-type]
    assert out.values[0] <= 4.0
    assert -1.0 <= out.values[1] <= 1.0
    assert out.cost < out.start_cost < FAILED_COST


def test_a_start_that_falls_is_returned_as_it_is() -> None:
    out = refine_fit(_Problem(), [2.0, 0.0], lambda cs: [None for _ in cs])  # type: ignore[arg-type]
    assert not out.improved
    assert list(out.values) == [2.0, 0.0]
    assert out.message == "fell"


def test_refine_and_designed_settings_are_checked() -> None:
    from zmpkit.errors import ParameterError
    from zmpkit.pipelines.identify_sim_config import IdentifySimConfig

    with pytest.raises(ParameterError, match=r"refine must be one of none, lm; got 'gn'"):
        IdentifySimConfig(self_test=True, refine="gn")
    with pytest.raises(ParameterError, match="it does not go with --window-pooling median"):
        IdentifySimConfig(self_test=True, refine="lm", window_pooling="median")
    with pytest.raises(ParameterError, match="--designed belongs to --self-test"):
        IdentifySimConfig(data=("x",), designed=True)


def test_a_designed_self_test_plan_adds_every_double_support_design() -> None:
    from zmpkit.experiments.double_support import DESIGNS
    from zmpkit.robots.registry import get_robot
    from zmpkit.simfit.self_test import self_test_plan

    for name in ("nao", "teo"):
        robot = get_robot(name, needs="fit")
        plain, designed = self_test_plan(robot, False), self_test_plan(robot, False, True)
        assert plain.designs == ()
        assert designed.designs == DESIGNS
        assert (designed.fit, designed.held_out) == (plain.fit, plain.held_out)


def test_identify_sim_refine_option_reaches_the_config(tmp_path, monkeypatch) -> None:
    """The CLI passes --refine and --designed through, and refuses a bad value in one line."""
    from click.testing import CliRunner

    from zmpkit.cli import identify as cli_identify

    seen = {}

    def fake_run(config, out_dir, progress=None, replica_progress=None):
        seen["config"] = config
        raise KeyboardInterrupt

    monkeypatch.setattr(cli_identify, "run_identify_sim", fake_run)
    runner = CliRunner()
    args = ["sim", "--self-test", "--designed", "--refine", "lm", "--out", str(tmp_path)]
    runner.invoke(cli_identify.identify_group, args)
    assert seen["config"].refine == "lm"
    assert seen["config"].designed
    bad = runner.invoke(cli_identify.identify_group, [*args[:4], "gn", *args[5:]])
    assert bad.exit_code == 2
    assert "'gn' is not one of 'none', 'lm'" in bad.output


def test_refinement_json_names_each_start_and_the_one_kept(tmp_path) -> None:
    import json

    from zmpkit.simfit.least_squares_refit import (
        LeastSquaresRefit,
        refinement_doc,
        refinement_line,
        write_refinement,
    )

    def refit(cost: float) -> LeastSquaresRefit:
        return LeastSquaresRefit(np.array([1.0, 2.0]), cost, 0.1, 7, 21, np.zeros((3, 2)), "ok")

    path = write_refinement(
        refinement_doc({"cma_best": refit(0.006), "nominal": refit(0.003)}, 0.008),
        tmp_path / "r.json",
    )
    doc = json.loads(path.read_text())
    assert doc["kept"] == "nominal"
    assert doc["starts"]["cma_best"]["cost"] == 0.006
    assert doc["starts"]["nominal"]["values"] == [1.0, 2.0]
    line = refinement_line(doc)
    assert line.endswith("from nominal 0.003 (21 rollouts); kept nominal")
    none_kept = write_refinement(
        refinement_doc({"nominal": refit(0.01)}, 0.008), tmp_path / "n.json"
    )
    assert json.loads(none_kept.read_text())["kept"] is None
    assert refinement_line(json.loads(none_kept.read_text())).endswith("CMA-ES's best kept")


@pytest.mark.slow
def test_a_refined_quick_self_test_keeps_the_cheapest_and_still_recovers(tmp_path) -> None:
    """``--refine lm`` on the quick self-test: the bar of the CMA-ES-only quick self-test.

    Measured without CMA-ES (Levenberg–Marquardt from the nominal values alone on the same
    walks): P gain −2.3 %, gear stiffness +9.0 %, where CMA-ES gets both within 1 %; hence
    the refinement also starts from CMA-ES's best, and the cheapest end is kept.
    """
    import json

    from zmpkit.pipelines.identify_sim import IdentifySimConfig, run_identify_sim

    config = IdentifySimConfig(
        self_test=True, quick=True, refine="lm", interval_replicas=0, figures=False
    )
    fit = run_identify_sim(config, tmp_path)
    doc = json.loads((tmp_path / "refinement.json").read_text())
    assert fit.refinement == doc
    ends = {name: start["cost"] for name, start in doc["starts"].items()}
    assert set(ends) == {"cma_best", "nominal"}
    assert ends["cma_best"] <= doc["cma_cost"]  # a refinement never ends above its start
    assert fit.cost == pytest.approx(min(doc["cma_cost"], *ends.values()))
    assert (doc["kept"] is None) == (fit.cost == doc["cma_cost"])
    for row in fit.recovery:
        assert row.identifiable, row
        assert abs(row.error_pct) < 10.0, row
