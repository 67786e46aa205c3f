"""The cost's Hessian and the marginal resolution: closed forms, an independent profile, a
valley of two parameters that trade off, and the identifiability verdict built on them."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray
from scipy.optimize import brentq, minimize

from zmpkit.robots.registry import get_robot
from zmpkit.simfit.cost import CostTerms
from zmpkit.simfit.cost_hessian import (
    conditional_resolutions,
    hessian_candidates,
    hessian_from_costs,
    marginal_resolutions,
    n_hessian_candidates,
    sloppy_directions,
)
from zmpkit.simfit.identifiability import (
    IDENTIFIABLE_WITHIN,
    PROFILE_STEP,
    ROUGHNESS_PROBES,
    ROUGHNESS_RISE,
    identifiability,
    visible_rise,
)
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.problem import FitProblem

NAO = get_robot("nao")


def _quadratic(c0: float, gradient: NDArray, hessian: NDArray, values: NDArray):
    """c(v) = c0 + g·δ + ½ δᵀHδ with δ = v / values − 1 (relative moves)."""

    def cost(v: NDArray) -> float:
        d = np.asarray(v, dtype=float) / values - 1.0
        return float(c0 + gradient @ d + 0.5 * d @ hessian @ d)

    return cost


def _spd(seed: int, n: int, low: float, high: float) -> NDArray:
    """A symmetric positive definite matrix with eigenvalues in [low, high]."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    return q @ np.diag(rng.uniform(low, high, n)) @ q.T


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n=st.integers(1, 6),
    c0=st.floats(0.0, 1.0),
    step=st.sampled_from([0.05, 0.1, 0.2]),
)
def test_the_hessian_of_a_quadratic_is_recovered_exactly(
    seed: int, n: int, c0: float, step: float
) -> None:
    rng = np.random.default_rng(seed)
    values = rng.uniform(0.5, 50.0, n) * rng.choice((-1.0, 1.0), n)
    a = rng.normal(size=(n, n))
    hessian = a + a.T  # any symmetric matrix, indefinite too
    gradient = rng.normal(size=n)  # not at an optimum: the differences cancel it
    cost = _quadratic(c0, gradient, hessian, values)
    candidates = hessian_candidates(values, step)
    assert len(candidates) == n_hessian_candidates(n)
    found = hessian_from_costs([cost(v) for v in candidates], cost(values), n, step)
    np.testing.assert_allclose(found, hessian, rtol=1e-7, atol=1e-7)


def _profiled_rise(hessian: NDArray, i: int, delta: float) -> float:
    """The cost rise with parameter i at ``delta`` and the others re-fitted (numerically)."""
    n = hessian.shape[0]
    others = [k for k in range(n) if k != i]

    def rise(rest: NDArray) -> float:
        d = np.zeros(n)
        d[i] = delta
        d[others] = rest
        return 0.5 * d @ hessian @ d

    if not others:
        return rise(np.zeros(0))
    return float(minimize(rise, np.zeros(n - 1), method="BFGS", tol=1e-14).fun)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 5), c0=st.floats(0.0, 0.1))
@pytest.mark.slow
def test_the_marginal_resolution_equals_a_profile_with_the_others_refitted(
    seed: int, n: int, c0: float
) -> None:
    hessian = _spd(seed, n, 0.5, 50.0)  # every direction stiff: no floppy cap involved
    rise = visible_rise(c0)
    marginal = marginal_resolutions(hessian, rise)
    conditional = conditional_resolutions(hessian, rise)
    for i in range(n):
        # independent: the delta at which the re-fitted cost rises by the visible rise
        profiled = brentq(lambda d, i=i: _profiled_rise(hessian, i, d) - rise, 1e-9, 1.0)
        assert marginal[i] == pytest.approx(profiled, rel=1e-5)
        assert conditional[i] == pytest.approx(math.sqrt(2 * rise / hessian[i, i]), rel=1e-12)
        assert marginal[i] >= conditional[i] * (1 - 1e-12)


def _valley_cost(v: NDArray) -> float:
    """Only 0.6 δ_gear + 0.4 δ_link shows (a straight valley in relative moves), and pid."""
    d = v / np.array([1200.0, 1800.0, 0.7]) - 1.0
    return 0.002 + 40.0 * (0.6 * d[0] + 0.4 * d[1]) ** 2 + 5.0 * d[2] ** 2


def test_two_parameters_that_trade_off_are_each_sharp_but_jointly_loose() -> None:
    """Each alone moves the cost; the two together along the valley do not; the loose
    direction names both, with opposite signs."""
    truth = np.array([1200.0, 1800.0, 0.7])
    cost = _valley_cost
    candidates = hessian_candidates(truth, PROFILE_STEP)
    hessian = hessian_from_costs([cost(v) for v in candidates], cost(truth), 3, PROFILE_STEP)
    rise = visible_rise(cost(truth))
    conditional = conditional_resolutions(hessian, rise)
    marginal = marginal_resolutions(hessian, rise)
    assert conditional[0] < 0.01  # each alone: sharp
    assert conditional[1] < 0.01
    # together: the valley is floppy, free over ±100 % along it, so each parameter moves
    # by its share of the valley's direction (0.4, -0.6) / |(0.4, -0.6)| before the cost rises
    assert marginal[0] == pytest.approx(0.4 / math.sqrt(0.52), rel=1e-3)
    assert marginal[1] == pytest.approx(0.6 / math.sqrt(0.52), rel=1e-3)
    assert marginal[2] == pytest.approx(conditional[2], rel=1e-9)  # independent: unchanged
    loose = sloppy_directions(hessian, rise, ["gear", "link", "pid"], IDENTIFIABLE_WITHIN)
    assert len(loose) == 1
    (name_a, a), (name_b, b) = loose[0].components
    assert {name_a, name_b} == {"gear", "link"}
    assert a * b < 0  # one stiffer, the other softer
    assert abs(a / b) == pytest.approx(0.4 / 0.6 if name_a == "gear" else 0.6 / 0.4)
    assert loose[0].resolution > 1.0  # flat but for rounding


def test_a_bent_valley_shows_its_bend_within_the_step() -> None:
    """Two compliances in series: only k1 k2 / (k1 + k2) shows. Its valley bends within
    ±10 %, which the secant Hessian counts as curvature (h² times the walls' steepness): the
    marginal resolution is then a lower bound, still far coarser than either profile."""
    truth = np.array([1200.0, 1800.0])

    def series(v: NDArray) -> float:
        return v[0] * v[1] / (v[0] + v[1])

    def cost(v: NDArray, steepness: float) -> float:
        return 0.002 + steepness * math.log(series(v) / series(truth)) ** 2

    rise = visible_rise(0.002)
    found = []
    for step in (0.1, 0.05, 0.02):
        costs = [cost(v, 40.0) for v in hessian_candidates(truth, step)]
        hessian = hessian_from_costs(costs, cost(truth, 40.0), 2, step)
        conditional = conditional_resolutions(hessian, rise)
        marginal = marginal_resolutions(hessian, rise)
        assert np.all(marginal > 5 * conditional)
        found.append(marginal[0])
    assert found[0] < found[1] < found[2]  # the smaller the step, the less bend it sees
    assert found[1] == pytest.approx(2 * found[0], rel=0.02)  # the bend's curvature ∝ h²


def test_a_flat_parameter_is_infinite_and_its_own_loose_direction() -> None:
    hessian = np.diag([100.0, 0.0, -3.0])  # the second flat, the third concave
    rise = 1e-3
    marginal = marginal_resolutions(hessian, rise)
    assert marginal[0] == pytest.approx(math.sqrt(2 * rise / 100.0))
    assert math.isinf(marginal[1])
    assert math.isinf(marginal[2])
    loose = sloppy_directions(hessian, rise, ["a", "b", "c"], 0.1)
    assert [d.components for d in loose] == [(("c", 1.0),), (("b", 1.0),)]  # loosest first
    assert all(math.isinf(d.resolution) for d in loose)


def test_a_failed_candidate_judges_nothing_identifiable() -> None:
    hessian = np.array([[1.0, np.nan], [np.nan, 1.0]])
    assert np.all(np.isinf(marginal_resolutions(hessian, 1e-3)))
    assert sloppy_directions(hessian, 1e-3, ["a", "b"], 0.1) == ()


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(2, 5), scale=st.floats(0.01, 100.0))
def test_resolutions_follow_a_permutation_and_scale_with_the_cost(
    seed: int, n: int, scale: float
) -> None:
    hessian = _spd(seed, n, 1e-3, 50.0)  # floppy directions included
    rise = 1e-3
    base = marginal_resolutions(hessian, rise)
    order = np.random.default_rng(seed).permutation(n)
    permuted = marginal_resolutions(hessian[np.ix_(order, order)], rise)
    np.testing.assert_allclose(permuted, base[order], rtol=1e-9)
    # a cost k times steeper is a rise k times smaller: every resolution the same
    np.testing.assert_allclose(marginal_resolutions(scale * hessian, scale * rise), base, rtol=1e-9)


class _QuadraticEvaluator:
    """An evaluator whose cost is a known function of the values (one experiment)."""

    def __init__(self, cost) -> None:
        self.cost = cost
        self.batches: list[int] = []

    def costs(self, candidates: Sequence) -> list[list[CostTerms]]:
        self.batches.append(len(candidates))
        return [
            [CostTerms(math.sqrt(self.cost(np.asarray(v))), 0.0, 0.0, 1.0, 0.0)] for v in candidates
        ]

    def close(self) -> None:
        pass


def test_identifiability_judges_on_the_marginal_resolution() -> None:
    parameters = (
        FitParameter("gear", "gear.stiffness", 1200.0, 300.0, 5000.0, "N·m/rad", True, "G"),
        FitParameter("link", "flex.stiffness", 1800.0, 400.0, 8000.0, "N·m/rad", True, "F"),
        FitParameter("pid", "stiffness", 0.7, 0.35, 1.0, "-", True, "M"),
    )
    truth = np.array([1200.0, 1800.0, 0.7])
    cost = _valley_cost
    problem = FitProblem(NAO, "M,G,F", parameters, {}, ())
    evaluator = _QuadraticEvaluator(cost)
    judged = identifiability(problem, evaluator, truth, cost(truth), np.full(3, 0.01))
    assert evaluator.batches == [n_hessian_candidates(3) + ROUGHNESS_PROBES]  # one batch
    gear, link, pid = judged.parameters
    assert gear.resolution < 0.01  # the profile alone would say yes
    assert link.resolution < 0.01
    assert not gear.identifiable
    assert not link.identifiable
    assert pid.identifiable
    assert pid.marginal_resolution < 0.02
    assert [name for name, _ in judged.sloppy[0].components] in (["gear", "link"], ["link", "gear"])
    assert gear.cost_minus == pytest.approx(cost(truth * [0.9, 1, 1]))
    assert gear.cost_plus == pytest.approx(cost(truth * [1.1, 1, 1]))


def _problem() -> FitProblem:
    parameters = (
        FitParameter("gear", "gear.stiffness", 1200.0, 300.0, 5000.0, "N·m/rad", True, "G"),
        FitParameter("link", "flex.stiffness", 1800.0, 400.0, 8000.0, "N·m/rad", True, "F"),
        FitParameter("pid", "stiffness", 0.7, 0.35, 1.0, "-", True, "M"),
    )
    return FitProblem(NAO, "M,G,F", parameters, {}, ())


def _separable_cost(v: NDArray) -> float:
    d = v / np.array([1200.0, 1800.0, 0.7]) - 1.0
    return 0.002 + 0.5 * float(d @ np.diag([4.0, 0.4, 0.04]) @ d)


def test_a_smooth_cost_keeps_the_plain_visible_rise() -> None:
    truth = np.array([1200.0, 1800.0, 0.7])
    judged = identifiability(
        _problem(), _QuadraticEvaluator(_separable_cost), truth, 0.002, np.full(3, 0.01)
    )
    assert judged.level == 0.002  # the centre: no spike
    assert judged.rise == pytest.approx(visible_rise(judged.level))
    assert ROUGHNESS_RISE * judged.roughness < judged.rise  # the plain rise holds
    rise = judged.rise
    expected = [math.sqrt(2 * rise / k) for k in (4.0, 0.4, 0.04)]
    got = [p.marginal_resolution for p in judged.parameters]
    assert got == pytest.approx(expected, rel=1e-9)  # 1.2, 3.9 and 12.3 %
    assert [p.identifiable for p in judged.parameters] == [True, True, False]


def test_a_spike_at_the_centre_and_a_rough_cost_raise_the_visible_rise() -> None:
    """A self-test's truth replays its recording exactly (a spike far below its neighbours),
    and a walk's cost jitters on small scales: the level is the neighbours', and a visible
    rise is twice the jitter's measured scatter."""
    truth = np.array([1200.0, 1800.0, 0.7])
    jitter = 4e-4

    def rough(v: NDArray) -> float:
        if np.array_equal(v, truth):
            return 1e-5  # the exact replay
        phase = float(np.sum(np.sin(2000.0 * v / truth)))  # deterministic, fast-varying
        return _separable_cost(v) + 1e-3 + jitter * phase

    judged = identifiability(_problem(), _QuadraticEvaluator(rough), truth, 1e-5, np.zeros(3))
    assert judged.level > 1e-3  # the neighbours' level, not the spike
    assert judged.roughness > jitter / 2
    assert judged.rise == pytest.approx(2.0 * judged.roughness)
    assert judged.parameters[0].identifiable  # 10 % raise it by 0.02, far above the jitter


def test_a_refined_point_without_a_cma_spread_is_judged_on_the_marginal_alone() -> None:
    """A Levenberg–Marquardt end has no CMA-ES spread: NaN, not a stale spread, and not 0 %."""
    truth = np.array([1200.0, 1800.0, 0.7])
    evaluator = _QuadraticEvaluator(_separable_cost)
    wide = identifiability(_problem(), evaluator, truth, 0.002, np.full(3, 0.5))
    refined = identifiability(_problem(), evaluator, truth, 0.002, np.full(3, np.nan))
    assert [p.identifiable for p in wide.parameters] == [False, False, False]  # spread 140 %+
    assert [p.identifiable for p in refined.parameters] == [True, True, False]
    assert "refined by Levenberg–Marquardt (no CMA-ES spread there): within 10 %" in (
        refined.parameters[0].reason
    )
    assert math.isnan(refined.parameters[0].cma_relative_std)
