"""The model-adequacy check: the best cost against the noise floor, the residuals' structure."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.robots.registry import get_robot
from zmpkit.simfit.adequacy import (
    ADEQUATE_RATIO,
    Adequacy,
    lag1_autocorrelation,
    model_adequacy,
)
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.outputs import adequacy_entry
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

NAO = get_robot("nao")


def test_lag1_autocorrelation_closed_forms() -> None:
    """Constant: (N-1)/N; alternating: -(N-1)/N; a sine of period P: about cos(2 pi / P)."""
    n = 50
    assert lag1_autocorrelation(np.ones(n)) == pytest.approx((n - 1) / n)
    alternating = np.where(np.arange(n) % 2 == 0, 1.0, -1.0)
    assert lag1_autocorrelation(alternating) == pytest.approx(-(n - 1) / n)
    t = np.arange(4000)
    sine = np.sin(2 * np.pi * t / 40)
    assert lag1_autocorrelation(sine) == pytest.approx(math.cos(2 * np.pi / 40), abs=1e-3)
    assert math.isnan(lag1_autocorrelation(np.zeros((10, 2))))
    both = np.column_stack([np.ones(n), np.zeros(n), alternating])  # the silent column skipped
    assert lag1_autocorrelation(both) == pytest.approx(0.0)


@given(
    st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=40).filter(
        lambda x: sum(v * v for v in x) > 1e-6
    ),
    st.floats(1e-3, 1e3),
)
def test_lag1_autocorrelation_is_bounded_and_scale_free(values: list[float], scale: float) -> None:
    r = np.array(values)
    rho = lag1_autocorrelation(r)
    assert -1.0 - 1e-12 <= rho <= 1.0 + 1e-12  # Cauchy-Schwarz
    assert lag1_autocorrelation(scale * r) == pytest.approx(rho, abs=1e-9)


@given(st.floats(1e-6, 10.0), st.floats(0.0, 5.0), st.floats(0.0, 50.0))
def test_the_verdict_follows_the_limit(floor: float, spread: float, best: float) -> None:
    check = Adequacy(best, floor, spread, 4, 0.5, 0.5)
    limit = max(ADEQUATE_RATIO * floor, floor + 3 * spread)
    assert check.limit == pytest.approx(limit)
    assert check.explains == (best <= limit)
    assert ("does not explain" in check.verdict) == (best > limit)
    assert ("not a precision" in check.verdict) == (best > limit)


@given(st.floats(0.0, 0.99), st.floats(1e-4, 0.2), st.integers(2, 12), st.floats(-0.5, 0.5))
def test_residuals_are_structured_beyond_the_replicas_prediction_bound(
    mean: float, spread: float, replicas: int, shift: float
) -> None:
    """r > r̄ + t_{0.99, K-1} s_r √(1 + 1/K): a cost the noise explains is then not enough."""
    from scipy.stats import t as student_t

    bound = mean + student_t.ppf(0.99, replicas - 1) * spread * math.sqrt(1 + 1 / replicas)
    lag = bound + shift
    check = Adequacy(0.1, 0.1, 0.01, replicas, lag, mean, spread)
    assert check.lag1_limit == pytest.approx(bound)
    assert check.structured == (lag > bound)
    assert check.explains == (lag <= bound)  # the cost lies at its floor
    if lag > bound:
        assert "smoother than the noise" in check.verdict
        assert adequacy_entry(check)["residuals_structured"] is True


def test_structure_is_not_judged_from_one_replica() -> None:
    check = Adequacy(0.1, 0.1, math.nan, 1, 0.99, 0.5, math.nan)
    assert check.structured is None
    assert check.explains is True  # the cost alone
    assert adequacy_entry(check)["residual_lag1_limit"] is None


def test_a_t_bound_from_four_replicas_matches_its_closed_form() -> None:
    """t_{0.99, 3} = 4.5407: four replicas at 0.72 ± 0.01 bound r at 0.72 + 0.0508."""
    check = Adequacy(0.05, 0.05, 0.005, 4, 0.80, 0.72, 0.01)
    assert check.lag1_limit == pytest.approx(0.72 + 4.5407 * 0.01 * math.sqrt(1.25), abs=1e-4)
    assert check.structured is True


def test_no_replica_no_verdict() -> None:
    check = Adequacy(0.1, math.nan, math.nan, 0, 0.9, math.nan)
    assert check.explains is None
    assert "not judged" in check.verdict
    entry = adequacy_entry(check)
    assert entry["explains_data"] is None
    assert entry["noise_floor"] is None


@pytest.fixture(scope="module")
def zmpip_problem(tmp_path_factory: pytest.TempPathFactory) -> FitProblem:
    """A zmpip walk of the shipped NAO; the quick parameters."""
    from helpers.simfit_data import record_feedback_walk

    folder: Path = record_feedback_walk(tmp_path_factory.mktemp("adequacy_walk"))
    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(NAO, None))
    return FitProblem(NAO, "M,G,S", params, doc, tuple(read_experiments([folder], NAO)))


@pytest.mark.slow
def test_the_recording_truth_explains_its_walk_and_a_wrong_model_does_not(
    zmpip_problem: FitProblem,
) -> None:
    """The shipped values (what walked) against values 30 % off, replicas of each."""
    right = model_adequacy(zmpip_problem, np.array([0.7, 1200.0]), replicas=3)
    assert right.replicas == 3
    assert right.noise_floor > 0.0  # fresh noise in a closed loop: never an exact replay
    assert right.explains is True
    wrong = model_adequacy(zmpip_problem, np.array([0.49, 700.0]), replicas=3)
    assert wrong.explains is False
    assert wrong.best_cost > right.best_cost
