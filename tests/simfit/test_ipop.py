"""IPOP-CMA-ES restarts on an analytic multimodal cost (no simulation).

The Rastrigin function on [-5.12, 5.12]^3,

.. math:: f(x) = 10 n + \\sum_i \\left(x_i^2 - 10 \\cos(2 \\pi x_i)\\right),

has its global minimum f = 0 at x = 0 (closed form) and a local minimum near every integer
point, where a single CMA-ES run with a small population stops.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest

from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.checkpoint import HISTORY_FILE, load_checkpoint
from zmpkit.simfit.cost import CostTerms
from zmpkit.simfit.optimizer import (
    CmaOptions,
    CmaResult,
    FitInterruptedError,
    FitProgress,
    run_cma,
)
from zmpkit.simfit.parameters import ParameterValues
from zmpkit.simfit.problem import FitProblem

RASTRIGIN_BOUND = 5.12
START = 3.0  # the first run starts near the local minimum at (3, 3, 3)


def rastrigin(x: np.ndarray) -> float:
    """The Rastrigin function (module docstring) [-]."""
    return float(10.0 * x.size + np.sum(x**2 - 10.0 * np.cos(2.0 * np.pi * x)))


class RastriginEvaluator:
    """An evaluator whose one experiment costs f(x): a joint term of sqrt(f), weight 1."""

    def costs(self, candidates: Sequence[ParameterValues]) -> list[list[CostTerms]]:
        f = [rastrigin(np.asarray(c, dtype=float)) for c in candidates]
        return [[CostTerms(float(np.sqrt(v)), 0.0, 0.0, 1.0, 0.0)] for v in f]

    def close(self) -> None:
        """Nothing to release."""


@pytest.fixture(scope="module")
def problem() -> FitProblem:
    b = RASTRIGIN_BOUND
    params = tuple(FitParameter(f"x{i}", f"x{i}", START, -b, b, "-") for i in range(3))
    return FitProblem(get_robot("nao"), "M", params, {}, ())


def _fit(problem: FitProblem, out: Path, **options: int) -> CmaResult:
    return run_cma(problem, RastriginEvaluator(), CmaOptions(**options), out)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 3])
def test_restarts_find_the_global_minimum_a_single_run_misses(
    problem: FitProblem, tmp_path: Path, seed: int
) -> None:
    budget = 1000  # generations per run: every run below stops on cma's own criteria first
    single = _fit(problem, tmp_path / "single", generations=budget, seed=seed)
    ipop = _fit(problem, tmp_path / "ipop", generations=budget, seed=seed, restarts=5)
    assert len(single.history) < budget  # it stopped by itself, not for lack of generations
    assert single.best_cost > 0.9  # a local minimum: f >= 0.995 away from x = 0
    assert np.max(np.abs(ipop.best_values)) < 1e-3  # the global minimiser, x = 0
    assert ipop.best_cost < 1e-4
    first_run = [r.best_cost for r in ipop.history if r.restart == 0]
    assert first_run == [r.best_cost for r in single.history]  # run 0 is the single run


def test_each_restart_doubles_the_population(problem: FitProblem, tmp_path: Path) -> None:
    result = _fit(problem, tmp_path, generations=8, popsize=6, restarts=3)
    runs = [r.restart for r in result.history]
    assert runs == sorted(runs)
    assert set(runs) == {0, 1, 2, 3}
    assert all(r.popsize == 6 * 2**r.restart for r in result.history)
    sizes = np.diff([0] + [r.evaluations for r in result.history])
    assert all(n == r.popsize for n, r in zip(sizes, result.history, strict=True))
    assert all(sum(r.restart == k for r in result.history) <= 8 for k in range(4))
    assert result.best_cost == min(r.best_cost for r in result.history)  # best of all runs
    written = json.loads((tmp_path / HISTORY_FILE).read_text())
    assert [(g["restart"], g["popsize"]) for g in written] == [
        (r.restart, r.popsize) for r in result.history
    ]


class _StopAt:
    """A progress callback that presses Ctrl-C after the ``k``-th generation."""

    def __init__(self, k: int) -> None:
        self.k = k

    def __call__(self, progress: FitProgress) -> None:
        if progress.generation == self.k:
            raise KeyboardInterrupt


def test_a_resumed_fit_continues_in_its_restart(problem: FitProblem, tmp_path: Path) -> None:
    options = CmaOptions(generations=6, seed=2, restarts=3)
    whole = run_cma(problem, RastriginEvaluator(), options, tmp_path / "whole")
    runs = [r.restart for r in whole.history]
    last_of_run0 = runs.index(1)  # generations finished when run 0 ended
    middle_of_run2 = runs.index(2) + 2
    for k in (last_of_run0, middle_of_run2):
        cut = tmp_path / f"cut{k}"
        with pytest.raises(FitInterruptedError):
            run_cma(problem, RastriginEvaluator(), options, cut, progress=_StopAt(k))
        assert load_checkpoint(cut).restart == runs[k - 1]  # interrupted in that run
        resumed = run_cma(problem, RastriginEvaluator(), options, cut, resume=cut)
        assert [(r.restart, r.popsize, r.best_cost, r.sigma) for r in resumed.history] == [
            (r.restart, r.popsize, r.best_cost, r.sigma) for r in whole.history
        ]
        assert np.array_equal(resumed.best_values, whole.best_values)
        assert np.array_equal(resumed.unit_std, whole.unit_std)
