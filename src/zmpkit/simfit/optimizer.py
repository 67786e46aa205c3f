"""CMA-ES over the normalised parameters (``cma``'s ask/tell), checkpointed every generation.

Each generation asks ``popsize`` candidates in [0, 1]^n (``cma``'s bound handling keeps
them inside), evaluates every candidate on every experiment through an
:class:`~zmpkit.simfit.backends.Evaluator`, tells the cost pooled over the
experiments (:mod:`~zmpkit.simfit.pooled_cost`: their mean, the logs' windows by their
median), and writes the checkpoint (:mod:`~zmpkit.simfit.checkpoint`) before
reporting progress. The random draws are
the checkpoint's (:mod:`~zmpkit.simfit.restarts`): a resumed fit draws the same candidates
as an uninterrupted one and ends exactly as it does.

IPOP-CMA-ES restarts (``restarts`` > 0; :mod:`~zmpkit.simfit.restarts`): each run has up
to ``generations`` generations; like ``generations``, ``restarts`` is a budget, so a
finished fit resumed with more restarts goes on with the next one. With a
:class:`~zmpkit.simfit.population.PopulationPlan` (``plan``) the backend's width sets the
population, each run's generations and the restarts that fit the wall-time budget
(:mod:`~zmpkit.simfit.population`).

Ctrl-C (KeyboardInterrupt) stops the fit between or during generations; the checkpoint
then holds every finished generation and :class:`FitInterruptedError` names it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ZmpkitError
from zmpkit.simfit.backends import Evaluator
from zmpkit.simfit.checkpoint import (
    Checkpoint,
    GenerationRecord,
    check_fingerprint,
    load_checkpoint,
    save_checkpoint,
)
from zmpkit.simfit.cma_state import MAX_POPSIZE, new_strategy
from zmpkit.simfit.cost import FORCE_SMOOTHING_S, ZMP_SMOOTHING_S
from zmpkit.simfit.parameters import from_unit, to_unit
from zmpkit.simfit.population import PopulationPlan, cma_default_popsize
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.restarts import (
    global_rng,
    restart,
    run_over,
    set_global_rng,
    unit_std,
    with_rng,
)

__all__ = [
    "MAX_POPSIZE",
    "MAX_RESTARTS",
    "CmaOptions",
    "CmaResult",
    "FitInterruptedError",
    "FitProgress",
    "run_cma",
]

MAX_RESTARTS = 9
"""Most IPOP restarts: the last run's population is 2^9 = 512 times the first's."""


class FitInterruptedError(ZmpkitError):
    """The fit was interrupted; every finished generation is in the checkpoint.

    Args:
        checkpoint: the checkpoint file.
        generation: finished generations.
    """

    def __init__(self, checkpoint: Path, generation: int) -> None:
        self.checkpoint = checkpoint
        self.generation = generation
        super().__init__(
            f"interrupted after generation {generation}; checkpoint {checkpoint}; "
            f"continue with --resume {checkpoint.parent}"
        )


@dataclass(frozen=True)
class CmaOptions:
    """Settings of the evolution strategy.

    Attributes:
        generations: generations to run (fewer if CMA-ES meets its own stop criteria).
        popsize: candidates per generation; None = ``cma``'s default 4 + 3 ln n.
        sigma0: initial step size in normalised coordinates [-].
        seed: seed of the strategy's random draws.
        restarts: IPOP restarts after the first run (0 = one run); each run has up to
            ``generations`` generations and twice the previous run's population.
        plan: the population sized to the backend (:mod:`~zmpkit.simfit.population`); when
            set, its population, per-run generations and restarts replace ``popsize``,
            ``generations`` and ``restarts``.
    """

    generations: int = 30
    popsize: int | None = None
    sigma0: float = 0.2
    seed: int = 1
    restarts: int = 0
    plan: PopulationPlan | None = None

    @property
    def first_popsize(self) -> int | None:
        """The first run's population (None: ``cma``'s default)."""
        return self.plan.popsize if self.plan is not None else self.popsize

    def run_cap(self, restart: int, popsize: int, spent: list[int]) -> int:
        """Generations of run ``restart`` of ``popsize``, ``spent`` generations before it."""
        if self.plan is None:
            return self.generations
        return self.plan.run_cap(restart, popsize, spent)

    def restart_allowed(self, restart: int, popsize: int, spent: list[int]) -> bool:
        """Whether restart ``restart`` of ``popsize`` runs after the generations ``spent``."""
        if self.plan is None:
            return restart <= self.restarts
        return self.plan.may_restart(restart, popsize, spent)


def _spent(state: Checkpoint, end: int | None = None) -> list[int]:
    """The population of each generation in ``state``'s history (up to ``end``)."""
    return [r.popsize for r in state.history[:end]]


def _run_generations(state: Checkpoint, options: CmaOptions) -> int:
    """The generations of the current run in ``state`` (its own, within the budget)."""
    popsize = int(state.strategy.popsize)
    return options.run_cap(state.restart, popsize, _spent(state, state.run_start))


def _may_restart(state: Checkpoint, options: CmaOptions) -> bool:
    """Whether the next IPOP run starts after the current one in ``state`` stopped."""
    popsize = 2 * int(state.strategy.popsize)
    return options.restart_allowed(state.restart + 1, popsize, _spent(state))


@dataclass(frozen=True)
class FitProgress:
    """What the progress callback gets after every generation.

    Attributes:
        generation: finished generations, over all runs.
        generations: generations planned: this run's budget plus every later run's.
        best_cost: best cost so far [-].
        eta_s: estimated remaining wall time, if every run used its budget [s].
        evaluations: candidates evaluated so far.
        restart: the current run: 0 the first, k the k-th restart.
        popsize: the current run's population.
    """

    generation: int
    generations: int
    best_cost: float
    eta_s: float
    evaluations: int
    restart: int = 0
    popsize: int = 0


ProgressCallback = Callable[[FitProgress], None]


@dataclass(frozen=True)
class CmaResult:
    """The outcome of the evolution strategy.

    Attributes:
        best_values: best parameter values found [units].
        best_cost: their cost [-].
        history: one record per generation (with its restart and population).
        unit_std: final standard deviation per parameter of the CMA-ES run that found the
            best, normalised [-].
        checkpoint: the checkpoint file.
    """

    best_values: NDArray[np.float64]
    best_cost: float
    history: tuple[GenerationRecord, ...]
    unit_std: NDArray[np.float64]
    checkpoint: Path


def fingerprint(problem: FitProblem, options: CmaOptions) -> dict[str, Any]:
    """What identifies a fit, for refusing to resume another one."""
    out: dict[str, Any] = {
        "robot": problem.robot.source,
        "sim_effects": problem.sim_effects,
        "parameters": [(p.name, p.path, p.nominal, p.lower, p.upper) for p in problem.parameters],
        "experiments": [e.name for e in problem.experiments],
        "popsize": _popsize_key(options.first_popsize, len(problem.parameters)),
        "sigma0": options.sigma0,
        "seed": options.seed,
        "zmp_smoothing_s": ZMP_SMOOTHING_S,  # its cost smooths the ZMP: not one from before
    }
    if problem.sensor_readings != "sampled":  # a checkpoint from before the option resumes
        out["sensor_readings"] = problem.sensor_readings
    if problem.window_pooling != "mean":
        out["window_pooling"] = problem.window_pooling
    if problem.models_loads:  # its cost charges the feet's forces: not one from before them
        out["force_smoothing_s"] = FORCE_SMOOTHING_S
    return out


def _popsize_key(popsize: int | None, n: int) -> int | None:
    """The fingerprint's population: None for ``cma``'s default, as fits before the plan."""
    return None if popsize is None or popsize == cma_default_popsize(n) else popsize


def _start(problem: FitProblem, options: CmaOptions) -> Checkpoint:
    x0 = to_unit(problem.parameters, [p.nominal for p in problem.parameters])
    draws = np.random.RandomState(options.seed)  # cma calls randn(lam, N); the checkpoint
    outer = global_rng()  # keeps its state
    np.random.seed(options.seed)  # noqa: NPY002 - any other draw cma makes
    strategy = new_strategy(x0, options.sigma0, options.first_popsize, draws)
    rng = global_rng()
    set_global_rng(outer)
    return Checkpoint(
        fingerprint(problem, options), strategy, draws, rng, 0, x0.tolist(), np.inf, []
    )


def _generation(state: Checkpoint, problem: FitProblem, evaluator: Evaluator) -> GenerationRecord:
    started = time.perf_counter()
    es = state.strategy
    candidates = with_rng(state, es.ask)
    values = [from_unit(problem.parameters, u) for u in candidates]
    per_experiment = evaluator.costs(values)
    costs = [problem.cost_of(row) for row in per_experiment]
    with_rng(state, lambda: es.tell(candidates, costs))
    best = int(np.argmin(costs))
    if costs[best] < state.best_cost:
        state.best_cost, state.best_unit = costs[best], np.asarray(candidates[best]).tolist()
        state.best_restart = state.restart
    state.generation += 1
    best_values = from_unit(problem.parameters, state.best_unit)
    return GenerationRecord(
        state.generation,
        (state.history[-1].evaluations if state.history else 0) + len(candidates),
        costs[best],
        state.best_cost,
        float(np.median(costs)),
        float(es.sigma),
        {p.name: float(v) for p, v in zip(problem.parameters, best_values, strict=True)},
        time.perf_counter() - started,
        state.restart,
        len(candidates),
    )


def _resume_state(problem: FitProblem, options: CmaOptions, resume: Path | None) -> Checkpoint:
    if resume is None:
        return _start(problem, options)
    state = load_checkpoint(resume)
    check_fingerprint(state.fingerprint, fingerprint(problem, options), resume)
    return state


def _progress(state: Checkpoint, options: CmaOptions, wall_per_eval_s: float) -> FitProgress:
    """Progress with the plan of the current and every later run at their full budgets."""
    popsize = int(state.strategy.popsize)
    left = max(0, state.run_start + _run_generations(state, options) - state.generation)
    evals, planned = left * popsize, state.generation + left
    spent = _spent(state) + [popsize] * left
    k, size = state.restart, popsize
    while k < MAX_RESTARTS and options.restart_allowed(k + 1, 2 * size, spent):
        k, size = k + 1, 2 * size
        run = options.run_cap(k, size, spent)
        evals, planned = evals + run * size, planned + run
        spent += [size] * run
    return FitProgress(
        state.generation,
        planned,
        state.best_cost,
        wall_per_eval_s * evals,
        int(state.history[-1].evaluations),
        state.restart,
        popsize,
    )


def run_cma(
    problem: FitProblem,
    evaluator: Evaluator,
    options: CmaOptions,
    out_dir: Path,
    resume: Path | None = None,
    progress: ProgressCallback | None = None,
) -> CmaResult:
    """Minimise the problem's cost; checkpoint into ``out_dir`` after every generation.

    Runs CMA-ES once, then ``options.restarts`` IPOP restarts (module docstring).

    Raises:
        FitInterruptedError: on Ctrl-C, naming the checkpoint.
        InputFileError: if ``resume`` holds no readable checkpoint of this format and
            ``cma`` version (:func:`~zmpkit.simfit.checkpoint.load_checkpoint`).
        ParameterError: if ``resume`` holds a checkpoint of another fit.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    state = _resume_state(problem, options, resume)
    path = save_checkpoint(state, out_dir)
    wall_s, evaluated = 0.0, 0
    try:
        while True:
            while not run_over(state, _run_generations(state, options)):
                record = _generation(state, problem, evaluator)
                state.history.append(record)
                path = save_checkpoint(state, out_dir)
                wall_s, evaluated = wall_s + record.wall_s, evaluated + record.popsize
                if progress is not None:
                    progress(_progress(state, options, wall_s / evaluated))
            if not _may_restart(state, options):
                break
            restart(state, options.seed, options.sigma0)
            path = save_checkpoint(state, out_dir)
    except KeyboardInterrupt:
        raise FitInterruptedError(path, state.generation) from None
    std = unit_std(state.strategy)
    if state.best_restart != state.restart and state.best_run_std is not None:
        std = state.best_run_std
    best = from_unit(problem.parameters, state.best_unit)
    return CmaResult(best, state.best_cost, tuple(state.history), np.asarray(std), path)
