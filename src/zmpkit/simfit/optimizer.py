"""CMA-ES over the normalised parameters (``cma``'s ask/tell), checkpointed every generation.

Each generation asks ``popsize`` candidates in [0, 1]^n (``cma``'s bound handling keeps
them inside), evaluates every candidate on every experiment through an
:class:`~zmpkit.simfit.backends.Evaluator`, tells the mean cost over the
experiments, and writes the checkpoint (:mod:`~zmpkit.simfit.checkpoint`) before
reporting progress. ``cma`` samples through its ``randn`` option, here a private
``RandomState`` seeded by the fit (pickled with the strategy, so it travels in the
checkpoint); any other draw it makes comes from numpy's global generator, whose state is
also kept in the checkpoint and swapped in only around ``ask``/``tell``. A resumed fit thus
draws the same candidates as an uninterrupted one and ends exactly as it does.

Ctrl-C (KeyboardInterrupt) stops the fit between or during generations; the checkpoint
then holds every finished generation and :class:`FitInterruptedError` names it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cma
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
from zmpkit.simfit.parameters import from_unit, to_unit
from zmpkit.simfit.problem import FitProblem

__all__ = ["CmaOptions", "CmaResult", "FitInterruptedError", "FitProgress", "run_cma"]


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
    """

    generations: int = 30
    popsize: int | None = None
    sigma0: float = 0.2
    seed: int = 1


@dataclass(frozen=True)
class FitProgress:
    """What the progress callback gets after every generation.

    Attributes:
        generation: finished generations.
        generations: generations planned.
        best_cost: best cost so far [-].
        eta_s: estimated remaining wall time [s].
        evaluations: candidates evaluated so far.
    """

    generation: int
    generations: int
    best_cost: float
    eta_s: float
    evaluations: int


ProgressCallback = Callable[[FitProgress], None]


@dataclass(frozen=True)
class CmaResult:
    """The outcome of the evolution strategy.

    Attributes:
        best_values: best parameter values found [units].
        best_cost: their cost [-].
        history: one record per generation.
        unit_std: CMA-ES's final standard deviation per parameter, normalised [-].
        checkpoint: the checkpoint file.
    """

    best_values: NDArray[np.float64]
    best_cost: float
    history: tuple[GenerationRecord, ...]
    unit_std: NDArray[np.float64]
    checkpoint: Path


def fingerprint(problem: FitProblem, options: CmaOptions) -> dict[str, Any]:
    """What identifies a fit, for refusing to resume another one."""
    return {
        "robot": problem.robot,
        "sim_effects": problem.sim_effects,
        "parameters": [(p.name, p.path, p.nominal, p.lower, p.upper) for p in problem.parameters],
        "experiments": [e.name for e in problem.experiments],
        "popsize": options.popsize,
        "sigma0": options.sigma0,
        "seed": options.seed,
    }


def _global_rng() -> Any:
    """Return NumPy's global random state (``cma`` may draw from it)."""
    return np.random.get_state()  # noqa: NPY002 - cma draws from the legacy global generator


def _set_global_rng(state: Any) -> None:
    np.random.set_state(state)  # noqa: NPY002 - cma draws from the legacy global generator


def _start(problem: FitProblem, options: CmaOptions) -> Checkpoint:
    x0 = to_unit(problem.parameters, [p.nominal for p in problem.parameters])
    draws = np.random.RandomState(options.seed)  # cma calls randn(lam, N); pickles with it
    opts: dict[str, Any] = {"bounds": [0.0, 1.0], "seed": np.nan, "randn": draws.randn}
    opts["verbose"] = -9
    if options.popsize is not None:
        opts["popsize"] = options.popsize
    outer = _global_rng()
    np.random.seed(options.seed)  # noqa: NPY002 - any other draw cma makes
    strategy = cma.CMAEvolutionStrategy(x0.tolist(), options.sigma0, opts)
    rng = _global_rng()
    _set_global_rng(outer)
    return Checkpoint(fingerprint(problem, options), strategy, rng, 0, x0.tolist(), np.inf, [])


def _with_rng(state: Checkpoint, call: Callable[[], Any]) -> Any:
    outer = _global_rng()
    _set_global_rng(state.rng_state)
    try:
        return call()
    finally:
        state.rng_state = _global_rng()
        _set_global_rng(outer)


def _generation(state: Checkpoint, problem: FitProblem, evaluator: Evaluator) -> GenerationRecord:
    started = time.perf_counter()
    es = state.strategy
    candidates = _with_rng(state, es.ask)
    values = [from_unit(problem.parameters, u) for u in candidates]
    per_experiment = evaluator.costs(values)
    costs = [float(np.mean([t.total(problem.weights) for t in row])) for row in per_experiment]
    _with_rng(state, lambda: es.tell(candidates, costs))
    best = int(np.argmin(costs))
    if costs[best] < state.best_cost:
        state.best_cost, state.best_unit = costs[best], np.asarray(candidates[best]).tolist()
    state.generation += 1
    best_values = from_unit(problem.parameters, state.best_unit)
    return GenerationRecord(
        state.generation,
        int(es.countevals),
        costs[best],
        state.best_cost,
        float(np.median(costs)),
        float(es.sigma),
        {p.name: float(v) for p, v in zip(problem.parameters, best_values, strict=True)},
        time.perf_counter() - started,
    )


def _resume_state(problem: FitProblem, options: CmaOptions, resume: Path | None) -> Checkpoint:
    if resume is None:
        return _start(problem, options)
    state = load_checkpoint(resume)
    check_fingerprint(state.fingerprint, fingerprint(problem, options), resume)
    return state


def run_cma(
    problem: FitProblem,
    evaluator: Evaluator,
    options: CmaOptions,
    out_dir: Path,
    resume: Path | None = None,
    progress: ProgressCallback | None = None,
) -> CmaResult:
    """Minimise the problem's cost; checkpoint into ``out_dir`` after every generation.

    Raises:
        FitInterruptedError: on Ctrl-C, naming the checkpoint.
        ParameterError: if ``resume`` holds a checkpoint of another fit.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    state = _resume_state(problem, options, resume)
    path = save_checkpoint(state, out_dir)
    session: list[float] = []
    try:
        while state.generation < options.generations and not state.strategy.stop():
            record = _generation(state, problem, evaluator)
            state.history.append(record)
            path = save_checkpoint(state, out_dir)
            session.append(record.wall_s)
            if progress is not None:
                eta = float(np.mean(session)) * (options.generations - state.generation)
                progress(
                    FitProgress(
                        state.generation,
                        options.generations,
                        state.best_cost,
                        eta,
                        record.evaluations,
                    )
                )
    except KeyboardInterrupt:
        raise FitInterruptedError(path, state.generation) from None
    es = state.strategy
    std = float(es.sigma) * np.sqrt(np.diag(es.sm.covariance_matrix))
    best = from_unit(problem.parameters, state.best_unit)
    return CmaResult(best, state.best_cost, tuple(state.history), std, path)
