"""Bias-corrected intervals from re-fitted replicas: closed forms, a toy estimator's coverage."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import t as student_t

from zmpkit.errors import ParameterError
from zmpkit.pipelines.identify_sim_config import IdentifySimConfig
from zmpkit.simfit.identifiability import ParameterIdentifiability
from zmpkit.simfit.local_refit import local_minimum
from zmpkit.simfit.noise_intervals import NoiseInterval
from zmpkit.simfit.outputs import write_intervals_csv
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.refit_intervals import RefitInterval, interval_scales, replica_intervals


def test_the_interval_is_the_closed_form_of_the_replicas_mean_and_scatter() -> None:
    # moves +2 %, +4 %, +3 %, +3 %: mean 3 %, sample sd sqrt(2/3) %
    estimates = np.array([[102.0], [104.0], [103.0], [103.0]])
    (interval,) = replica_intervals(["k"], [100.0], [100.0], estimates)
    sd = math.sqrt(2.0 / 3.0) / 100.0
    half = float(student_t.ppf(0.975, 3)) * sd * math.sqrt(1.25)
    assert interval.bias == pytest.approx(0.03)
    assert interval.spread == pytest.approx(sd)
    assert interval.corrected == pytest.approx(97.0)
    assert interval.half_width == pytest.approx(half)
    assert (interval.lower, interval.upper) == pytest.approx((97.0 - 100 * half, 97.0 + 100 * half))
    assert interval.kind == "pipeline_refits"
    assert "bias" in interval.method


def test_one_replica_leaves_the_interval_unmeasured_and_none_the_bias() -> None:
    (one,) = replica_intervals(["k"], [1.0], [1.0], np.array([[1.1]]))
    assert one.bias == pytest.approx(0.1)
    assert math.isnan(one.half_width)
    assert not one.covers(1.0)
    (none,) = replica_intervals(["k"], [1.0], [1.0], np.empty((0, 1)))
    assert math.isnan(none.bias)
    assert none.replicas == 0


def test_a_zero_estimate_is_scaled_by_its_range() -> None:
    offset = FitParameter("offset", "ft.offset", 0.0, -2.0, 2.0, "N", effect="S")
    gain = FitParameter("gain", "pid.p", 1.0, 0.5, 2.0, "-", effect="M")
    assert interval_scales([offset, gain], [0.0, -1.5]) == [4.0, 1.5]


def _coverage(bias: float, sigma: float, replicas: int, trials: int, correct: bool) -> float:
    """How often the interval of a toy estimator covers its truth.

    The toy pipeline: an estimate is ``truth + bias + noise`` (in relative terms), its
    replicas are the same pipeline run on a robot that *is* the estimate.
    """
    rng = np.random.default_rng(29)
    truth, hits = 1.0, 0
    for _ in range(trials):
        estimate = truth * (1.0 + bias + sigma * rng.normal())
        refits = estimate * (1.0 + bias + sigma * rng.normal(size=(replicas, 1)))
        (interval,) = replica_intervals(["k"], [estimate], [estimate], refits)
        if not correct:
            interval = NoiseInterval("k", estimate, interval.half_width, replicas)
        hits += interval.covers(truth)
    return hits / trials


@pytest.mark.slow
def test_the_toy_estimators_interval_covers_its_truth_95_percent_of_the_time() -> None:
    # bias 4 %, noise 1 % (about the gear stiffness's on two held-out truths): 2000 trials
    # give a coverage known to about ±0.5 %
    assert 0.935 <= _coverage(0.04, 0.01, 6, 2000, correct=True) <= 0.965
    assert 0.935 <= _coverage(0.0, 0.01, 4, 2000, correct=True) <= 0.965
    # the same width about the uncorrected estimate misses a bias of four noise widths
    assert _coverage(0.04, 0.01, 6, 2000, correct=False) < 0.5


@settings(max_examples=40, deadline=None)
@given(
    st.floats(0.2, 5.0),
    st.floats(-0.3, 0.3),
    st.floats(-0.3, 0.3),
    st.floats(0.5, 20.0),
)
def test_local_minimum_finds_a_quadratic_costs_minimum(
    a: float, x0: float, y0: float, b: float
) -> None:
    # an elongated, tilted bowl: the re-fit must move both coordinates together
    def cost(u: np.ndarray) -> float:
        dx, dy = u[0] - x0, u[1] - y0
        return float(a * (dx + dy) ** 2 + b * (dx - dy) ** 2)

    u, value, spent = local_minimum(cost, 2, step=0.03, tolerance=1e-6, max_evaluations=600)
    np.testing.assert_allclose(u, [x0, y0], atol=1e-3)
    assert value == pytest.approx(0.0, abs=1e-5)
    assert spent <= 600


@settings(max_examples=30)
@given(st.floats(-0.2, 0.2), st.floats(1e-4, 0.05), st.integers(2, 8), st.integers(0, 2**32 - 1))
def test_shifting_every_replica_shifts_the_centre_not_the_width(
    shift: float, sigma: float, k: int, seed: int
) -> None:
    rng = np.random.default_rng(seed)
    refits = 10.0 * (1.0 + sigma * rng.normal(size=(k, 1)))
    (base,) = replica_intervals(["k"], [10.0], [10.0], refits)
    (moved,) = replica_intervals(["k"], [10.0], [10.0], refits + 10.0 * shift)
    assert moved.bias == pytest.approx(base.bias + shift, abs=1e-12)
    assert moved.half_width == pytest.approx(base.half_width, rel=1e-9, abs=1e-12)
    assert moved.corrected == pytest.approx(base.corrected - 10.0 * shift, abs=1e-9)


def test_the_intervals_csv_says_which_interval(tmp_path) -> None:
    refit = RefitInterval("gear", 800.0, 800.0, (0.02, 0.04, 0.03))
    noise = NoiseInterval("pid", 0.6, 0.02, 4)
    text = write_intervals_csv(tmp_path / "intervals.csv", [refit, noise]).read_text()
    header, gear, pid = text.splitlines()
    assert header.split(",")[-1] == "kind"
    assert gear.split(",")[5] == "3"
    assert gear.endswith("pipeline_refits")
    assert pid.split(",")[5] == ""
    assert pid.endswith("noise_only")
    assert float(gear.split(",")[4]) == pytest.approx(776.0)


@pytest.mark.parametrize("bad", [1, -1, True, 2.0])
def test_interval_replicas_is_zero_or_at_least_two(bad: object) -> None:
    with pytest.raises(ParameterError, match="interval_replicas must be 0"):
        IdentifySimConfig(data=("x",), interval_replicas=bad)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("resolution", "marginal", "spread", "identifiable", "why"),
    [
        (0.03, 0.04, 0.002, True, "both within 10 %"),
        (0.03, 0.25, 0.002, False, "the others compensate it beyond 10 %"),
        (0.30, 0.40, 0.002, False, "beyond 10 %"),
        (0.30, math.inf, 0.002, False, "no visible cost rise within ±100 %"),
    ],
)
def test_identifiability_says_why(
    resolution: float, marginal: float, spread: float, identifiable: bool, why: str
) -> None:
    entry = ParameterIdentifiability(
        "k", 1.0, 0.1, 0.1, 0.1, resolution, spread, identifiable, marginal
    )
    assert entry.reason.endswith(why) or entry.reason.startswith(why)
    if math.isfinite(marginal):
        assert f"±{100 * marginal:.2g} %" in entry.reason
