"""``zmpkit identify sim``: fit the simulator's effect parameters to recorded experiments.

Paper B §II: "The simulation is optimized by Evolutionary Algorithms to fit a physical
robot." The fitted parameters of the chosen effects (M, I, G, F, S, and C for mass/CoM)
are found by CMA-ES (:mod:`zmpkit.simfit`) from recorded experiments — walk folders or
step datasets, as the robot's fit replays them, using only the commanded angles, encoders,
F-T ZMP and IMU — with rollouts in MuJoCo thread-pool batches (default), on a process pool or
a Ray cluster, checkpointed every generation.

:func:`run_identify_sim` writes into the output folder only as it goes: the checkpoint
(``checkpoint.json`` and ``checkpoint.npz``, data only: :mod:`zmpkit.simfit.checkpoint`),
``history.json`` and, with ``self_test``, the recorded experiments under ``self_test/``.
:func:`~zmpkit.pipelines.identify_sim_files.write_identify_sim` writes the rest:
``fitted_truth.yaml`` (loadable as ``--truth``), ``fitted_parameters.yaml``,
``cost_history.csv``, ``identifiability.csv``, ``reproduction.csv``, figures, the report and,
with ``self_test``, ``recovery.csv``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from zmpkit.pipelines.identify_sim_config import IdentifySimConfig
from zmpkit.simfit.adequacy import Adequacy, model_adequacy, replica_recordings
from zmpkit.simfit.backends import make_evaluator
from zmpkit.simfit.checkpoint import load_checkpoint
from zmpkit.simfit.cost_hessian import CostDirection
from zmpkit.simfit.experiments import Experiment, read_experiments, simulated_effects
from zmpkit.simfit.identifiability import Identifiability, ParameterIdentifiability, identifiability
from zmpkit.simfit.least_squares_refit import (
    REFINEMENT_FILE,
    ResidualEvaluator,
    refine_fit,
    refinement_doc,
    write_refinement,
)
from zmpkit.simfit.noise_intervals import noise_intervals
from zmpkit.simfit.optimizer import CmaOptions, CmaResult, ProgressCallback, run_cma
from zmpkit.simfit.parameters import FitParameter, nominal_values
from zmpkit.simfit.population import PopulationPlan, cma_default_popsize, population_plan
from zmpkit.simfit.problem import FitProblem, simulate
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.refit_intervals import ParameterInterval, refit_intervals
from zmpkit.simfit.self_test import (
    RecoveryRow,
    perturbed_values,
    record_experiments,
    recovery_rows,
    self_test_plan,
)
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc
from zmpkit.simfit.validation import ReproductionCheck, reproduction_check

__all__ = [
    "IdentifySimConfig",
    "IdentifySimResult",
    "Replay",
    "replay_experiments",
    "run_identify_sim",
]


@dataclass(frozen=True)
class Replay:
    """One experiment replayed with the fitted values.

    Attributes:
        experiment: the recorded experiment (its signals are the recording).
        simulated: the simulated signals with the fitted values.
        check: their trunk oscillation and joint error compared.
    """

    experiment: Experiment
    simulated: RecordedSignals
    check: ReproductionCheck


@dataclass(frozen=True)
class IdentifySimResult:
    """What a simulator fit produced.

    Attributes:
        config: what was asked.
        problem: the fit problem (robot, simulated effects, parameters, base truth, the
            fitted experiments).
        parameters: the fitted parameters.
        fitted: fitted value per parameter name [units].
        cost: the best cost [-].
        cma: the evolution strategy's outcome (history, spread, checkpoint).
        identifiability: per parameter, whether the data pin it down.
        fit_checks: trunk oscillation and joint error on the fitted experiments.
        held_out_checks: the same on the held-out experiments.
        replays: the fitted, then the held-out experiments replayed with the fitted values.
        recovery: self-test only: truth vs fit per parameter.
        files: every file written, by role (the checkpoint until
            :func:`~zmpkit.pipelines.identify_sim_files.write_identify_sim`).
        started_s: when the run started [s since the epoch].
        sloppy_directions: combinations of parameters the data leave loose (coarser than
            :data:`~zmpkit.simfit.identifiability.IDENTIFIABLE_WITHIN`), loosest first.
        adequacy: whether the fitted model explains the data (best cost against the noise
            floor, residual structure: :mod:`~zmpkit.simfit.adequacy`); None if not checked.
        intervals: per parameter, its 95 % interval: bias-corrected from replicas recorded
            through the data's pipeline and re-fitted (:mod:`~zmpkit.simfit.refit_intervals`)
            for walk logs (walked again for a log of ``zmpkit walk``, each window replayed
            again for any other), else the noise-only one
            (:mod:`~zmpkit.simfit.noise_intervals`); each says which (``method``). A
            precision only when the model explains the data.
        sim_effects: the effects the simulator ran: the fitted ones and those the recorded
            walks ran with (:func:`~zmpkit.simfit.experiments.simulated_effects`).
    """

    config: IdentifySimConfig
    problem: FitProblem
    parameters: tuple[FitParameter, ...]
    fitted: dict[str, float]
    cost: float
    cma: CmaResult
    identifiability: tuple[ParameterIdentifiability, ...]
    fit_checks: tuple[ReproductionCheck, ...]
    held_out_checks: tuple[ReproductionCheck, ...]
    replays: tuple[Replay, ...] = ()
    recovery: tuple[RecoveryRow, ...] = ()
    files: dict[str, Path] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)
    sloppy_directions: tuple[CostDirection, ...] = ()
    adequacy: Adequacy | None = None
    sim_effects: str = ""
    intervals: tuple[ParameterInterval, ...] = ()
    refinement: dict | None = None


def _experiments(
    config: IdentifySimConfig, base_doc: dict, parameters: tuple[FitParameter, ...], out: Path
) -> tuple[list[Experiment], list[Experiment], np.ndarray | None]:
    """(fit experiments, held-out experiments, hidden truth values or None)."""
    if not config.self_test:
        windows = (config.window_s, config.burn_in_s)
        held = read_experiments(config.held_out, config.robot, *windows) if config.held_out else []
        return read_experiments(config.data, config.robot, *windows), held, None
    truth = perturbed_values(parameters, config.seed)
    plan = self_test_plan(config.robot, config.quick, config.designed)
    fit_dirs, held_dirs = record_experiments(
        config.robot,
        plan,
        base_doc,
        parameters,
        truth,
        config.physics_effects,
        config.seed,
        out / "self_test",
    )
    return (
        read_experiments(fit_dirs, config.robot),
        read_experiments(held_dirs, config.robot),
        truth,
    )


def run_identify_sim(
    config: IdentifySimConfig,
    out_dir: str | Path,
    progress: ProgressCallback | None = None,
    replica_progress: Callable[[int, int], None] | None = None,
) -> IdentifySimResult:
    """Fit the simulator to the recorded experiments, checkpointing into ``out_dir``.

    Args:
        config: the fit.
        out_dir: output folder (created if missing); the checkpoint, the history and a
            self-test's recordings are written there as the fit goes, nothing else.
        progress: called after every generation with a
            :class:`~zmpkit.simfit.optimizer.FitProgress`.
        replica_progress: called with (replicas done, replicas) as the intervals' replicas
            are recorded again and re-fitted (:mod:`~zmpkit.simfit.refit_intervals`).

    Raises:
        InputFileError: on an unreadable experiment folder or base truth, or a checkpoint
            that is missing, damaged, of an older format or of another ``cma`` version
            (refused before anything is written).
        ParameterError: on a resume of another fit, or ``backend="ray"`` without Ray.
        FitInterruptedError: on Ctrl-C, naming the checkpoint to resume from.
    """
    started_s = time.time()
    out = Path(out_dir)
    resume = Path(config.resume) if config.resume is not None else None
    if resume is not None:
        load_checkpoint(resume)  # refuse a bad checkpoint before anything is read or written
    params = config.fit_parameters()
    base_doc = load_truth_doc(base_truth_path(config.robot, config.truth))
    # Recorded experiments are read before the output folder exists: bad input leaves none.
    recorded = None if config.self_test else _experiments(config, base_doc, params, out)
    out.mkdir(parents=True, exist_ok=True)
    fit_exps, held_exps, truth = recorded or _experiments(config, base_doc, params, out)
    problem = FitProblem(
        config.robot,
        simulated_effects(config.sim_effects, [*fit_exps, *held_exps]),
        params,
        base_doc,
        tuple(fit_exps),
        config.weights,
        config.sensor_readings,
        config.window_pooling,
    )
    cma_result, judged, refinement = _fit(config, problem, out, resume, progress)
    intervals = _intervals(config, problem, cma_result.best_values, replica_progress)
    result = _fit_result(
        config, problem, cma_result, judged, held_exps, truth, started_s, intervals
    )
    return replace(result, refinement=refinement)


def _fit(
    config: IdentifySimConfig,
    problem: FitProblem,
    out: Path,
    resume: Path | None,
    progress: ProgressCallback | None,
) -> tuple[CmaResult, Identifiability, dict | None]:
    """CMA-ES on ``problem`` (checkpointed into ``out``), refined, then judged.

    Returns the fit, each parameter's identifiability and the refinement's document
    (``refinement.json``; None without a refinement).
    """
    evaluator = make_evaluator(problem, config.backend, config.workers, config.address)
    try:
        plan = _population(config, problem, evaluator.width, resume)
        options = CmaOptions(
            config.n_generations,
            plan.popsize,
            config.sigma0,
            config.seed,
            config.restarts or 0,
            plan,
        )
        cma_result = run_cma(problem, evaluator, options, out, resume, progress)
        cma_result, refinement = _refined(config, problem, cma_result, out)
        judged = identifiability(
            problem, evaluator, cma_result.best_values, cma_result.best_cost, cma_result.unit_std
        )
    finally:
        evaluator.close()
    return cma_result, judged, refinement


def _refined(
    config: IdentifySimConfig, problem: FitProblem, cma_result: CmaResult, out: Path
) -> tuple[CmaResult, dict | None]:
    """The cheapest of CMA-ES's best and Levenberg–Marquardt's ends (``refine == "lm"``).

    Levenberg–Marquardt starts twice: from CMA-ES's best and from the catalogue's nominal
    values (on the built-in walker's whole catalogue CMA-ES's 440 rollouts ended in a basin
    costlier than the one a refinement from the nominal values reaches). Its rollouts run on this
    machine's CPU (``config.workers``) whatever the backend; ``refinement.json`` says what
    each start did.
    """
    if config.refine == "none":
        return cma_result, None
    starts = {"cma_best": cma_result.best_values, "nominal": nominal_values(problem.parameters)}
    residuals = ResidualEvaluator(problem, config.workers)
    try:
        refits = {name: refine_fit(problem, start, residuals) for name, start in starts.items()}
    finally:
        residuals.close()
    doc = refinement_doc(refits, cma_result.best_cost)
    write_refinement(doc, out / REFINEMENT_FILE)
    if doc["kept"] is None:
        return cma_result, doc
    best = refits[doc["kept"]]
    no_spread = np.full(len(problem.parameters), np.nan)  # CMA-ES's spread is not about it
    kept = replace(cma_result, best_values=best.values, best_cost=best.cost, unit_std=no_spread)
    return kept, doc


def _population(
    config: IdentifySimConfig, problem: FitProblem, width: int, resume: Path | None
) -> PopulationPlan:
    """The population, generations and restarts on a backend of ``width``.

    A resumed fit whose population was sized to its backend keeps that population (the
    checkpoint's), whatever the width of the backend it resumes on.
    """
    plan = population_plan(
        len(problem.parameters), width, config.n_generations, config.popsize, config.restarts
    )
    if resume is not None and config.popsize is None:
        started = load_checkpoint(resume).fingerprint.get("popsize")
        default = cma_default_popsize(len(problem.parameters))
        plan = replace(plan, popsize=started if isinstance(started, int) else default)
    return plan


def _fit_result(
    config: IdentifySimConfig,
    problem: FitProblem,
    cma_result: CmaResult,
    judged: Identifiability,
    held_exps: list[Experiment],
    truth: np.ndarray | None,
    started_s: float,
    intervals: tuple[ParameterInterval, ...] | None,
) -> IdentifySimResult:
    """The fit judged: adequacy, noise intervals, replays and, in a self-test, recovery."""
    best, params = cma_result.best_values, problem.parameters
    replicas = replica_recordings(problem, best)
    adequacy = model_adequacy(problem, best, recordings=replicas)
    if intervals is None:
        intervals = noise_intervals(problem, best, judged.hessian, replicas)
    fit_replays = replay_experiments(problem, list(problem.experiments), best)
    held_replays = replay_experiments(problem, held_exps, best)
    ident = judged.parameters
    recovery: tuple[RecoveryRow, ...] = ()
    if truth is not None:
        recovery = tuple(recovery_rows(params, truth, best, [i.identifiable for i in ident]))
    return IdentifySimResult(
        config=config,
        problem=problem,
        parameters=params,
        fitted={p.name: float(v) for p, v in zip(params, best, strict=True)},
        cost=cma_result.best_cost,
        cma=cma_result,
        identifiability=ident,
        fit_checks=tuple(r.check for r in fit_replays),
        held_out_checks=tuple(r.check for r in held_replays),
        replays=fit_replays + held_replays,
        recovery=recovery,
        files={"checkpoint": cma_result.checkpoint},
        started_s=started_s,
        sloppy_directions=judged.sloppy,
        adequacy=adequacy,
        sim_effects=problem.sim_effects,
        intervals=intervals,
    )


def _intervals(
    config: IdentifySimConfig,
    problem: FitProblem,
    best: np.ndarray,
    progress: Callable[[int, int], None] | None,
) -> tuple[ParameterInterval, ...] | None:
    """The bias-corrected intervals; None where the data's pipeline cannot be re-run."""
    if config.interval_replicas == 0:
        return None
    return refit_intervals(
        problem, best.tolist(), config.interval_replicas, progress, config.workers
    )


def replay_experiments(
    problem: FitProblem, experiments: list[Experiment], values: np.ndarray
) -> tuple[Replay, ...]:
    """Simulate each experiment with the fitted values and compare it with its recording."""
    held = FitProblem(
        problem.robot,
        problem.sim_effects,
        problem.parameters,
        problem.base_doc,
        tuple(experiments),
        problem.weights,
        problem.sensor_readings,
        problem.window_pooling,
    )
    replays = []
    for i, experiment in enumerate(experiments):
        simulated = simulate(held, values, i)
        check = reproduction_check(experiment.name, experiment.signals, simulated)
        replays.append(Replay(experiment, simulated, check))
    return tuple(replays)
