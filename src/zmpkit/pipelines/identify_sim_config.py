"""The settings of ``zmpkit identify sim``: what is fitted, to which data, how.

:class:`IdentifySimConfig` checks its values on creation (:class:`~zmpkit.errors.ParameterError`
naming what is valid); :mod:`zmpkit.pipelines.identify_sim` runs it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from zmpkit.errors import ParameterError
from zmpkit.robots.registry import DEFAULT_FIT_ROBOT, get_robot
from zmpkit.robots.robot import Robot
from zmpkit.simfit.backends import BACKENDS, DEFAULT_WORKERS
from zmpkit.simfit.cost import CostWeights
from zmpkit.simfit.least_squares_refit import REFINEMENTS
from zmpkit.simfit.optimizer import MAX_POPSIZE, MAX_RESTARTS
from zmpkit.simfit.parameters import FitParameter, default_parameters, parse_fit_effects
from zmpkit.simfit.pooled_cost import check_window_pooling
from zmpkit.simfit.problem import check_sensor_readings
from zmpkit.simfit.refit_intervals import REFIT_REPLICAS
from zmpkit.simfit.shooting_window import DEFAULT_BURN_IN_S, DEFAULT_WINDOW_S, check_window

__all__ = ["DEFAULT_GENERATIONS", "QUICK_GENERATIONS", "IdentifySimConfig"]

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
            CMA-ES's 4 + 3 ln n, or the backend's width if larger, with fewer generations
            (:mod:`~zmpkit.simfit.population`).
        restarts: IPOP-CMA-ES restarts after the first run, each from a random mean with
            twice the previous population (0 to :data:`~zmpkit.simfit.optimizer.MAX_RESTARTS`;
            ``popsize`` times 2^restarts at most
            :data:`~zmpkit.simfit.optimizer.MAX_POPSIZE`); ``generations`` is per run. None
            = as many as the fit's wall-time budget allows (:mod:`~zmpkit.simfit.population`).
        sigma0: initial CMA-ES step, fraction of each parameter's (log-)range [-].
        seed: seed of CMA-ES and, in a self-test, of the hidden truth and the sensor noise.
        quick: small fit (2–3 parameters; short experiments in a self-test).
        self_test: record experiments from a virtual robot with hidden perturbed truth,
            fit them, and compare (``recovery.csv``).
        designed: a self-test also records and fits the designed double-support
            experiments (:mod:`zmpkit.experiments.double_support`).
        refine: after CMA-ES, ``"lm"`` refines its best by Levenberg–Marquardt on the cost's
            residuals (:mod:`~zmpkit.simfit.least_squares_refit`), kept where cheaper;
            ``"none"`` does not.
        weights: weights of the cost terms.
        sensor_model: simulate the sensors as the base truth describes them (S: F-T filter,
            rate, quantisation, noise with a fixed seed; encoder resolution), so the
            simulated signals pass through the same sensor chain as the recorded ones.
        sensor_readings: with the sensor model, ``"sampled"`` (the whole chain, noise with a
            fixed seed and quantisation) or ``"expected"`` (no noise, no quantisation: a
            smooth cost; :func:`~zmpkit.simfit.truth_doc.expected_readings`).
        figures: draw the figures.
        window_pooling: how a walk log's windows enter the cost, ``"mean"`` or ``"median"``
            (:mod:`~zmpkit.simfit.pooled_cost`).
        window_s: a walk log's multiple-shooting window [s]
            (:mod:`~zmpkit.simfit.shooting_window`).
        burn_in_s: the unscored start of each window [s].
        interval_replicas: walk logs: replicas recorded through the data's pipeline
            (a ``zmpkit walk`` log walked again, any other log's windows replayed again) and
            re-fitted for the bias-corrected 95 % intervals
            (:mod:`~zmpkit.simfit.refit_intervals`); 0: the noise-only intervals
            (:mod:`~zmpkit.simfit.noise_intervals`).
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
    restarts: int | None = None
    sigma0: float = 0.2
    seed: int = 1
    quick: bool = False
    self_test: bool = False
    designed: bool = False
    refine: str = "none"
    weights: CostWeights = field(default_factory=CostWeights)
    sensor_model: bool = True
    figures: bool = True
    sensor_readings: str = "sampled"
    window_pooling: str = "mean"
    window_s: float = DEFAULT_WINDOW_S
    burn_in_s: float = DEFAULT_BURN_IN_S
    interval_replicas: int = REFIT_REPLICAS

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
        if self.refine not in REFINEMENTS:
            raise ParameterError(
                f"refine must be one of {', '.join(REFINEMENTS)}; got {self.refine!r}"
            )
        if self.refine != "none" and self.window_pooling != "mean":
            raise ParameterError(
                "--refine lm minimises the mean of the experiments' costs (a sum of squares); "
                f"it does not go with --window-pooling {self.window_pooling}"
            )
        if self.designed and not self.self_test:
            raise ParameterError(
                "--designed belongs to --self-test (a recording of the designed experiments "
                "is given as DATA: a step dataset)"
            )
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
        check_window_pooling(self.window_pooling)
        check_window(self.window_s, self.burn_in_s)
        _check_interval_replicas(self.interval_replicas)
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


def _check_interval_replicas(value: object) -> None:
    ok = isinstance(value, int) and not isinstance(value, bool) and (value == 0 or value >= 2)
    if not ok:
        raise ParameterError(
            "interval_replicas must be 0 (noise-only intervals) or an integer >= 2 (a "
            f"scatter needs two re-fits); got {value!r}"
        )


def _check_restarts(restarts: object, popsize: int | None) -> None:
    if restarts is None:
        return
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
