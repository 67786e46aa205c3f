"""The design math: a set's resolutions from its experiments' costs, and the greedy choice."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.simfit.cost_hessian import hessian_candidates
from zmpkit.simfit.experiment_design import (
    ExperimentCosts,
    design_candidates,
    greedy_design,
    judge_set,
)
from zmpkit.simfit.identifiability import (
    IDENTIFIABLE_WITHIN,
    PROFILE_STEP,
    roughness_candidates,
    visible_rise,
)

NOMINAL = np.array([2.0, 500.0, 0.03])


def _experiment(name: str, curvature: np.ndarray) -> ExperimentCosts:
    """A quadratic cost c = δᵀ A δ in relative moves δ = v / v0 - 1, A = diag(curvature)."""
    a = np.diag(curvature)
    costs = []
    for v in design_candidates(NOMINAL):
        d = v / NOMINAL - 1.0
        costs.append(float(d @ a @ d))
    return ExperimentCosts(name, np.array(costs))


def test_candidates_are_the_centre_the_hessian_moves_and_the_probes() -> None:
    cands = design_candidates(NOMINAL)
    moves = hessian_candidates(NOMINAL, PROFILE_STEP)
    probes = roughness_candidates(NOMINAL)
    assert len(cands) == 1 + len(moves) + len(probes)
    np.testing.assert_array_equal(cands[0], NOMINAL)
    np.testing.assert_array_equal(cands[1], moves[0])
    np.testing.assert_array_equal(cands[-1], probes[-1])


def test_a_quadratic_cost_gives_the_closed_form_resolution() -> None:
    # c = a δ1² alone: H11 = 2a, the resolution sqrt(2 Δc / H11) = sqrt(Δc / a); the others
    # leave the cost flat, so they are not pinned.
    a = 0.5
    judged = judge_set([_experiment("one", np.array([a, 0.0, 0.0]))], 3)
    rise = visible_rise(0.0, judged.roughness)
    assert judged.conditional[0] == pytest.approx(math.sqrt(rise / a), rel=1e-9)
    assert judged.marginal[0] == pytest.approx(math.sqrt(rise / a), rel=1e-9)
    assert judged.pinned == (True, False, False)
    assert math.isinf(judged.marginal[1])
    assert math.isinf(judged.marginal[2])


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.0, 2.0), min_size=3, max_size=3), st.floats(0.0, 2.0))
def test_a_set_costs_the_mean_of_its_experiments(first: list[float], scale: float) -> None:
    """The set's Hessian is that of the mean cost: here diag((A1 + A2) / 2)."""
    one = _experiment("one", np.array(first))
    two = _experiment("two", scale * np.ones(3))
    both = judge_set([one, two], 3)
    mean = _experiment("mean", (np.array(first) + scale) / 2.0)
    alone = judge_set([mean], 3)
    np.testing.assert_allclose(both.marginal, alone.marginal, rtol=1e-9)
    assert both.experiments == ("one", "two")


def test_two_experiments_each_pinning_one_parameter_pin_both_together() -> None:
    only_first = _experiment("first", np.array([1.0, 0.0, 0.0]))
    only_second = _experiment("second", np.array([0.0, 1.0, 0.0]))
    flat = _experiment("flat", np.zeros(3))
    chosen = greedy_design([flat, only_first, only_second], 3)
    assert [j.experiments[-1] for j in chosen][:2] in (["first", "second"], ["second", "first"])
    assert chosen[-1].pinned == (True, True, False)
    assert "flat" not in chosen[-1].experiments
    assert len(chosen) == 2


def test_an_experiment_that_adds_nothing_is_not_recommended() -> None:
    strong = _experiment("strong", np.array([1.0, 1.0, 1.0]))
    same = _experiment("same", np.array([1.0, 1.0, 1.0]))
    chosen = greedy_design([strong, same], 3)
    assert len(chosen) == 1
    assert all(chosen[0].pinned)
    assert max(chosen[0].marginal) < IDENTIFIABLE_WITHIN


def test_a_set_needs_an_experiment() -> None:
    with pytest.raises(ValueError, match="at least one"):
        judge_set([], 3)
