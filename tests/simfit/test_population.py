"""The population sized to the backend's width, and IPOP restarts within the wall-time budget.

Closed forms (cma's own default population, the module's worked GPU example), hypothesis
properties of the budget, and fits on the Rastrigin function (``test_ipop``'s analytic cost)
whose single run stops early, so the budget left goes to restarts.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import cma
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.simfit.cost import CostTerms
from zmpkit.simfit.optimizer import CmaOptions, run_cma
from zmpkit.simfit.parameters import ParameterValues
from zmpkit.simfit.population import (
    batches,
    cma_default_popsize,
    generations_for,
    population_plan,
)
from zmpkit.simfit.problem import FitProblem

from .test_ipop import RastriginEvaluator, problem  # noqa: F401 - the fixture


class WideRastrigin(RastriginEvaluator):
    """The Rastrigin evaluator, declared to evaluate ``width`` candidates at once."""

    def __init__(self, width: int) -> None:
        self.width = width
        self.generations: list[int] = []

    def costs(self, candidates: Sequence[ParameterValues]) -> list[list[CostTerms]]:
        self.generations.append(len(candidates))
        return super().costs(candidates)


@pytest.mark.parametrize("n", [1, 2, 3, 7, 12, 40])
def test_default_popsize_is_cmas(n: int) -> None:
    es = cma.CMAEvolutionStrategy([0.5] * max(n, 2), 0.2, {"verbose": -9})
    if n >= 2:
        assert cma_default_popsize(n) == es.popsize
    else:
        assert cma_default_popsize(1) == 4  # 4 + 3 ln 1


def test_the_worked_gpu_example() -> None:
    plan = population_plan(n=2, width=256, generations=30)
    assert plan.popsize == 256
    assert plan.run_generations(256) == math.ceil(30 * math.log(6) / math.log(256)) == 10
    assert plan.run_generations(512) == 9
    assert plan.budget == 30
    assert plan.may_restart(1, 512, [256] * 10)  # 10 + 9 x 2 = 28 <= 30
    assert not plan.may_restart(2, 1024, [256] * 10 + [512] * 9)  # 28 + 8 x 4 > 30


def test_a_narrow_backend_keeps_todays_fit() -> None:
    plan = population_plan(n=2, width=2, generations=30)
    assert plan.popsize == 6
    assert plan.run_generations(6) == 30
    assert plan.budget == 30 * 3
    assert not plan.may_restart(1, 12, [6] * 30)  # the full first run spent the budget
    assert plan.may_restart(1, 12, [6] * 8)  # a run cma stopped early leaves 66 batches
    assert plan.run_cap(1, 12, [6] * 8) == 11  # of its 22 generations of 6 batches
    assert not plan.may_restart(1, 12, [6] * 9)  # 63 batches: 10 of 22 generations


def test_a_users_population_and_restarts_are_kept() -> None:
    plan = population_plan(n=3, width=256, generations=20, popsize=12, restarts=2)
    assert plan.popsize == 12
    assert not plan.scaled
    assert plan.run_generations(48) == 20
    assert plan.may_restart(2, 48, [12] * 1000)
    assert not plan.may_restart(3, 96, [])


@pytest.mark.parametrize(("width", "generations"), [(0, 30), (4, 0)])
def test_bad_plans_are_refused(width: int, generations: int) -> None:
    with pytest.raises(ParameterError, match="must be >= 1"):
        population_plan(2, width, generations)


@settings(max_examples=200, deadline=None)
@given(
    n=st.integers(1, 60),
    width=st.integers(1, 4096),
    generations=st.integers(1, 200),
)
def test_full_runs_never_overspend_the_budget(n: int, width: int, generations: int) -> None:
    plan = population_plan(n, width, generations)
    assert plan.popsize >= cma_default_popsize(n)
    spent = [plan.popsize] * plan.run_generations(plan.popsize)
    first = sum(batches(p, width) for p in spent)
    size, restart = plan.popsize, 0
    while plan.may_restart(restart + 1, 2 * size, spent):
        restart, size = restart + 1, 2 * size
        run = plan.run_cap(restart, size, spent)
        assert run >= math.ceil(0.5 * plan.run_generations(size))
        spent += [size] * run
    total = sum(batches(p, width) for p in spent)
    assert total <= max(plan.budget, first)
    assert first <= plan.budget or restart == 0


@settings(max_examples=200, deadline=None)
@given(
    n=st.integers(1, 60),
    generations=st.integers(1, 200),
    small=st.integers(2, 10_000),
    factor=st.integers(1, 50),
)
def test_more_candidates_never_get_more_generations(
    n: int, generations: int, small: int, factor: int
) -> None:
    assert generations_for(small * factor, n, generations) <= generations_for(small, n, generations)
    assert 1 <= generations_for(small, n, generations) <= generations


@pytest.mark.slow
def test_budget_left_by_an_early_stop_goes_to_restarts(
    problem: FitProblem,  # noqa: F811 - the fixture
    tmp_path: Path,
) -> None:
    """The first run stops by itself in a Rastrigin local minimum; restarts use the rest."""
    evaluator = WideRastrigin(width=1)
    plan = population_plan(3, 1, generations=1000)
    result = run_cma(problem, evaluator, CmaOptions(plan=plan, seed=1), tmp_path)
    restarts = {r.restart for r in result.history}
    assert max(restarts) >= 1
    spent = sum(batches(g, 1) for g in evaluator.generations)
    assert spent <= plan.budget
    first = [r for r in result.history if r.restart == 0]
    assert len(first) < plan.run_generations(plan.popsize)  # it stopped early
    assert [r.popsize for r in result.history] == evaluator.generations


def test_a_wide_backend_fits_its_width_in_fewer_generations(
    problem: FitProblem,  # noqa: F811 - the fixture
    tmp_path: Path,
) -> None:
    evaluator = WideRastrigin(width=64)
    plan = population_plan(3, 64, generations=30)
    result = run_cma(problem, evaluator, CmaOptions(plan=plan, seed=1), tmp_path)
    first = [r for r in result.history if r.restart == 0]
    assert {r.popsize for r in first} == {64}
    assert len(first) <= plan.run_generations(64) == math.ceil(30 * math.log(7) / math.log(64))
    spent = sum(batches(g, 64) for g in evaluator.generations)
    assert spent <= plan.budget == 30
    assert np.isfinite(result.best_cost)


def test_a_fit_resumed_on_a_narrower_backend_keeps_its_population(
    problem: FitProblem,  # noqa: F811 - the fixture
    tmp_path: Path,
) -> None:
    from zmpkit.pipelines.identify_sim import _population
    from zmpkit.pipelines.identify_sim_config import IdentifySimConfig

    wide = population_plan(3, 64, generations=2)
    run_cma(problem, WideRastrigin(64), CmaOptions(plan=wide, seed=1), tmp_path)
    config = IdentifySimConfig(self_test=True, generations=2)
    resumed = _population(config, problem, width=2, resume=tmp_path)
    assert resumed.popsize == 64
    fresh = _population(config, problem, width=2, resume=None)
    assert fresh.popsize == cma_default_popsize(3)


@pytest.mark.needs_warp
def test_widths_of_the_backends(problem: FitProblem) -> None:  # noqa: F811 - the fixture
    from zmpkit.simfit.batch_backend import BatchEvaluator

    assert BatchEvaluator(problem, threads=3).width == 3
    assert BatchEvaluator(problem, threads=3, warp_device="cpu").width == 1


def test_a_pools_width_is_its_workers_shared_by_the_experiments(
    problem: FitProblem,  # noqa: F811 - the fixture
) -> None:
    from dataclasses import replace

    from zmpkit.simfit.pool_backend import LocalPoolEvaluator

    three = replace(problem, experiments=(None, None, None))  # three experiments, never run
    pool = LocalPoolEvaluator(three, workers=16)  # processes start on the first task
    try:
        assert pool.width == 16 // 3
    finally:
        pool.close()
