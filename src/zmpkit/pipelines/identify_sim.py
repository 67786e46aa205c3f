"""``zmpkit identify sim``: fit the simulator's effect parameters to recorded experiments.

Paper B §II: "The simulation is optimized by Evolutionary Algorithms to fit a physical
robot." The fitted parameters of the chosen effects (M, I, G, F, S, and C for mass/CoM)
are found by CMA-ES (:mod:`zmpkit.simfit`) from recorded experiments — walk folders or
step datasets, as the robot's fit replays them, using only the commanded angles, encoders,
F-T ZMP and IMU — with rollouts in MuJoCo thread-pool batches (default), on a process pool or
a Ray cluster, checkpointed every generation.

Writes into the output folder: the checkpoint (``checkpoint.json`` and ``checkpoint.npz``,
data only: :mod:`zmpkit.simfit.checkpoint`) and ``history.json``; ``fitted_truth.yaml``
(loadable as ``--truth``), ``fitted_parameters.yaml``, ``cost_history.csv``,
``identifiability.csv``, ``reproduction.csv``, figures; with ``self_test``, the recorded
experiments under ``self_test/`` and ``recovery.csv``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.pipelines.identify_sim_report import reproduction_checks, write_fit_files
from zmpkit.robots.registry import DEFAULT_FIT_ROBOT, get_robot
from zmpkit.robots.robot import Robot
from zmpkit.simfit.adequacy import Adequacy, model_adequacy, replica_recordings
from zmpkit.simfit.backends import BACKENDS, DEFAULT_WORKERS, make_evaluator
from zmpkit.simfit.checkpoint import load_checkpoint
from zmpkit.simfit.cost import CostWeights
from zmpkit.simfit.cost_hessian import CostDirection
from zmpkit.simfit.experiments import Experiment, read_experiments, simulated_effects
from zmpkit.simfit.identifiability import ParameterIdentifiability, identifiability
from zmpkit.simfit.noise_intervals import NoiseInterval, noise_intervals
from zmpkit.simfit.optimizer import (
    MAX_POPSIZE,
    MAX_RESTARTS,
    CmaOptions,
    CmaResult,
    ProgressCallback,
    run_cma,
)
from zmpkit.simfit.parameters import (
    FitParameter,
    default_parameters,
    parse_fit_effects,
)
from zmpkit.simfit.problem import FitProblem, check_sensor_readings
from zmpkit.simfit.self_test import (
    RecoveryRow,
    perturbed_values,
    record_experiments,
    recovery_rows,
    self_test_plan,
    write_recovery_csv,
)
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc
from zmpkit.simfit.validation import ReproductionCheck

__all__ = [
    "IdentifySimConfig",
    "IdentifySimResult",
    "run_identify_sim",
]

DEFAULT_GENERATIONS = 40
QUICK_GENERATIONS = 30


@dataclass(frozen=True)
class IdentifySimConfig:
    """``zmpkit identify sim DATA... --robot R --effects M,G --out DIR [...]``.

    Attributes:
        data: recorded experiment folders (walk folders or step datasets); empty
            with ``self_test``.
        robot: the robot (it needs a fit catalogue); a registry name or ``robot.yaml`` path
            given from Python is resolved once, here. Files record its
            :attr:`~zmpkit.robots.robot.Robot.source`.
        effects: letters of the effects whose parameters are fitted (``M,I,G,F,S,C``); the
            simulator runs with these effects on (C is not a switch).
        parameters: fit only these catalogue names; None = all of the effects (quick: the
            robot's quick parameters where they belong to the effects, see
            :attr:`~zmpkit.robots.robot.FitSpec.quick_parameters`).
        truth: base truth file holding every unfitted value; None = the shipped one.
        held_out: experiment folders not fitted, only checked (``--held-out``).
        backend: ``"local"`` (thread-pool batches), ``"pool"`` (process pool), ``"serial"``
            or ``"ray"``.
        address: Ray cluster address (``--address``), only with ``backend="ray"``.
        workers: threads of the local batches, or processes of the pool.
        resume: a folder of an interrupted fit to continue (``--resume``).
        generations: CMA-ES generations; None = 40, or 30 with ``quick``.
        popsize: candidates per generation (the first run's, with restarts); None =
            CMA-ES's 4 + 3 ln n.
        restarts: IPOP-CMA-ES restarts after the first run, each from a random mean with
            twice the previous population (0 to :data:`~zmpkit.simfit.optimizer.MAX_RESTARTS`;
            ``popsize`` times 2^restarts at most
            :data:`~zmpkit.simfit.optimizer.MAX_POPSIZE`); ``generations`` is per run.
        sigma0: initial CMA-ES step, fraction of each parameter's (log-)range [-].
        seed: seed of CMA-ES and, in a self-test, of the hidden truth and the sensor noise.
        quick: small fit (2–3 parameters; short experiments in a self-test).
        self_test: record experiments from a virtual robot with hidden perturbed truth,
            fit them, and compare (``recovery.csv``).
        weights: weights of the cost terms.
        sensor_model: simulate the sensors as the base truth describes them (S: F-T filter,
            rate, quantisation, noise with a fixed seed; encoder resolution), so the
            simulated signals pass through the same sensor chain as the recorded ones.
        sensor_readings: with the sensor model, ``"sampled"`` (the whole chain, noise with a
            fixed seed and quantisation) or ``"expected"`` (no noise, no quantisation: a
            smooth cost; :func:`~zmpkit.simfit.truth_doc.expected_readings`).
        figures: draw the figures.
    """

    data: tuple[str, ...] = ()
    robot: Robot = field(default_factory=lambda: get_robot(DEFAULT_FIT_ROBOT, needs="fit"))
    effects: str = "M,G"
    parameters: tuple[str, ...] | None = None
    truth: str | None = None
    held_out: tuple[str, ...] = ()
    backend: str = "local"
    address: str | None = None
    workers: int = DEFAULT_WORKERS
    resume: str | None = None
    generations: int | None = None
    popsize: int | None = None
    restarts: int = 0
    sigma0: float = 0.2
    seed: int = 1
    quick: bool = False
    self_test: bool = False
    weights: CostWeights = field(default_factory=CostWeights)
    sensor_model: bool = True
    figures: bool = True
    sensor_readings: str = "sampled"

    def __post_init__(self) -> None:
        object.__setattr__(self, "robot", get_robot(self.robot, needs="fit"))
        object.__setattr__(self, "effects", ",".join(parse_fit_effects(self.effects)))
        object.__setattr__(self, "data", tuple(str(d) for d in self.data))
        if self.backend not in BACKENDS:
            raise ParameterError(
                f"backend must be one of {', '.join(BACKENDS)}; got {self.backend!r}"
            )
        if self.address is not None and self.backend != "ray":
            raise ParameterError(f"--address is for --backend ray; got backend {self.backend!r}")
        if self.self_test and self.data:
            raise ParameterError("--self-test records its own experiments; give no DATA with it")
        if not self.self_test and not self.data:
            kind = self.robot.require_fit().experiment
            what = "a walk folder" if kind == "walk" else "a step dataset"
            raise ParameterError(f"give at least one DATA folder ({what}), or --self-test")
        _positive_int("generations", self.generations, allow_none=True)
        _positive_int("popsize", self.popsize, allow_none=True)
        _check_restarts(self.restarts, self.popsize)
        _positive_int("workers", self.workers)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"seed must be an integer >= 0; got {self.seed!r}")
        if not 0.0 < self.sigma0 <= 0.5:
            raise ParameterError(f"sigma0 must be in (0, 0.5]; got {self.sigma0!r}")
        check_sensor_readings(self.sensor_readings)
        self.fit_parameters()  # validates the parameter names against the effects

    @property
    def n_generations(self) -> int:
        """Generations to run."""
        if self.generations is not None:
            return self.generations
        return QUICK_GENERATIONS if self.quick else DEFAULT_GENERATIONS

    @property
    def physics_effects(self) -> str:
        """The fitted effect letters that switch physics on (all but C and S)."""
        letters = [x for x in self.effects.split(",") if x not in ("C", "S")]
        return ",".join(letters) if letters else "none"

    @property
    def sim_effects(self) -> str:
        """Effect letters the simulator runs with: the physics, plus S for the sensors."""
        sensors = self.sensor_model or "S" in self.effects.split(",")
        physics = self.physics_effects
        if not sensors:
            return physics
        return "S" if physics == "none" else f"{physics},S"

    def fit_parameters(self) -> tuple[FitParameter, ...]:
        """The fitted parameters."""
        chosen = default_parameters(self.robot, self.effects, self.parameters)
        if self.parameters is not None or not self.quick:
            return chosen
        names = self.robot.require_fit().quick_parameters
        quick = [p for p in chosen if p.name in names]
        return tuple(quick) if len(quick) >= 2 else chosen[:3]


def _positive_int(name: str, value: object, allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ParameterError(f"{name} must be an integer >= 1; got {value!r}")


def _check_restarts(restarts: object, popsize: int | None) -> None:
    if isinstance(restarts, bool) or not isinstance(restarts, int) or restarts < 0:
        raise ParameterError(f"restarts must lie in [0, {MAX_RESTARTS}]; got {restarts!r}")
    if restarts > MAX_RESTARTS:
        raise ParameterError(f"restarts must lie in [0, {MAX_RESTARTS}]; got {restarts!r}")
    if popsize is not None and popsize * 2**restarts > MAX_POPSIZE:
        raise ParameterError(
            f"popsize {popsize} doubled at each of {restarts} restarts exceeds {MAX_POPSIZE} "
            f"candidates; with this popsize restarts must lie in "
            f"[0, {(MAX_POPSIZE // popsize).bit_length() - 1}]"
        )


@dataclass(frozen=True)
class IdentifySimResult:
    """What a simulator fit produced.

    Attributes:
        config: what was asked.
        parameters: the fitted parameters.
        fitted: fitted value per parameter name [units].
        cost: the best cost [-].
        cma: the evolution strategy's outcome (history, spread, checkpoint).
        identifiability: per parameter, whether the data pin it down.
        fit_checks: trunk oscillation and joint error on the fitted experiments.
        held_out_checks: the same on the held-out experiments.
        recovery: self-test only: truth vs fit per parameter.
        files: every file written, by role.
        started_s: when the run started [s since the epoch].
        sloppy_directions: combinations of parameters the data leave loose (coarser than
            :data:`~zmpkit.simfit.identifiability.IDENTIFIABLE_WITHIN`), loosest first.
        adequacy: whether the fitted model explains the data (best cost against the noise
            floor, residual structure: :mod:`~zmpkit.simfit.adequacy`); None if not checked.
        intervals: per parameter, the 95 % interval the data's noise leaves
            (:mod:`~zmpkit.simfit.noise_intervals`); a precision only when the model
            explains the data.
        sim_effects: the effects the simulator ran: the fitted ones and those the recorded
            walks ran with (:func:`~zmpkit.simfit.experiments.simulated_effects`).
    """

    config: IdentifySimConfig
    parameters: tuple[FitParameter, ...]
    fitted: dict[str, float]
    cost: float
    cma: CmaResult
    identifiability: tuple[ParameterIdentifiability, ...]
    fit_checks: tuple[ReproductionCheck, ...]
    held_out_checks: tuple[ReproductionCheck, ...]
    recovery: tuple[RecoveryRow, ...] = ()
    files: dict[str, Path] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)
    sloppy_directions: tuple[CostDirection, ...] = ()
    adequacy: Adequacy | None = None
    sim_effects: str = ""
    intervals: tuple[NoiseInterval, ...] = ()


def _experiments(
    config: IdentifySimConfig, base_doc: dict, parameters: tuple[FitParameter, ...], out: Path
) -> tuple[list[Experiment], list[Experiment], np.ndarray | None]:
    """(fit experiments, held-out experiments, hidden truth values or None)."""
    if not config.self_test:
        held = read_experiments(config.held_out, config.robot) if config.held_out else []
        return read_experiments(config.data, config.robot), held, None
    truth = perturbed_values(parameters, config.seed)
    plan = self_test_plan(config.robot, config.quick)
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
    config: IdentifySimConfig, out_dir: str | Path, progress: ProgressCallback | None = None
) -> IdentifySimResult:
    """Fit the simulator to the recorded experiments; write the results to ``out_dir``.

    Args:
        config: the fit.
        out_dir: output folder (created if missing); the checkpoint is written there.
        progress: called after every generation with a
            :class:`~zmpkit.simfit.optimizer.FitProgress`.

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
    )
    options = CmaOptions(
        config.n_generations, config.popsize, config.sigma0, config.seed, config.restarts
    )
    evaluator = make_evaluator(problem, config.backend, config.workers, config.address)
    try:
        cma_result = run_cma(problem, evaluator, options, out, resume, progress)
        judged = identifiability(
            problem, evaluator, cma_result.best_values, cma_result.best_cost, cma_result.unit_std
        )
    finally:
        evaluator.close()
    replicas = replica_recordings(problem, cma_result.best_values)
    adequacy = model_adequacy(problem, cma_result.best_values, recordings=replicas)
    intervals = noise_intervals(problem, cma_result.best_values, judged.hessian, replicas)
    figures = out if config.figures else None
    fit_checks, fit_files = reproduction_checks(problem, fit_exps, cma_result.best_values, figures)
    held_checks, held_files = reproduction_checks(
        problem, held_exps, cma_result.best_values, figures
    )
    ident = judged.parameters
    files = write_fit_files(
        problem,
        cma_result,
        judged,
        (fit_checks, held_checks),
        out,
        config.figures,
        adequacy,
        intervals,
    )
    files |= fit_files | held_files
    recovery: tuple[RecoveryRow, ...] = ()
    if truth is not None:
        recovery = tuple(
            recovery_rows(params, truth, cma_result.best_values, [i.identifiable for i in ident])
        )
        files["recovery"] = write_recovery_csv(list(recovery), out / "recovery.csv")
    fitted = {p.name: float(v) for p, v in zip(params, cma_result.best_values, strict=True)}
    return IdentifySimResult(
        config,
        params,
        fitted,
        cma_result.best_cost,
        cma_result,
        ident,
        fit_checks,
        held_checks,
        recovery,
        files,
        started_s,
        judged.sloppy,
        adequacy,
        problem.sim_effects,
        intervals,
    )
