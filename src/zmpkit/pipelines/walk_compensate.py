"""The ``zmpkit walk compensate`` pipeline: paper B §III.C and §III.E on a walking robot.

Methods: ``alg1`` (Algorithm 1, offline multibody-ZMP compensation on the design model),
``alg2`` (Algorithm 2, online on the measured ZMP; with ``zmpip`` it rewrites the reference of
the feedback walk's observed preview control, paper B's line 3), ``half-sine``, ``sawtooth``,
``fourier`` (periodic offsets tuned over simulated walks, :mod:`zmpkit.compensate.tuning`),
and ``auto`` (tunes every shape, keeps the one with the lowest tuning objective). Every method
is judged on validation walks that tuning never saw, against the same walks without compensation:
open loop (paper B's simulation), other noise seeds and 0.15 and 0.25 m/s; with feedback
(``controller`` ``zmpip`` or ``dcm``, as paper B's robot walks), tuning scores each candidate
on walks at two speeds and two step durations (a fall is a failure), and every validation
walk differs from all of them in speed, step duration and robot (gear stiffness ±15–30 %,
:data:`HELD_OUT_WALKS`). A compensation that makes a validation walk fall that stands without
it is rejected (``rejected`` in ``summary.json``, and the report says so). "Peak" is the
trunk-pitch spectrum's amplitude at the step frequency; "std" the trunk pitch's standard
deviation over the steady walk; the summary's values are their means over the validation
walks.

The walks were designed for paper B's robot at its 0.2 m/s
(:data:`~zmpkit.robots.robot.DEFAULT_WALK_SPEED_MPS`); on another robot every speed and speed
change above is scaled by the robot's walking speed over 0.2 m/s
(:attr:`CompensateConfig.speed_scale`: 0.5 for a robot that walks at 0.1 m/s; step durations
are kept), and the tuning speed is the robot's walking speed unless one is given.

Writes ``summary.json`` (exactly :data:`SUMMARY_KEYS`, plus ``iteration_rms_m`` for
``alg1``), ``compensation.json`` (tuned parameters and tuning history), ``report.html`` and
the figures; tuning walks are cached under ``cache/`` (or ``cache_dir``) as they finish, so
a rerun resumes.
"""

from __future__ import annotations

import multiprocessing
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit import _validate
from zmpkit.compensate.algorithm1 import compensate_abstraction
from zmpkit.compensate.algorithm2 import Algorithm2Parameters
from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.compensate.methods import (
    CompensatedWalk,
    walk_with_algorithm1,
    walk_with_algorithm2,
    walk_with_offset,
)
from zmpkit.compensate.offsets import OFFSET_SHAPES, OffsetParameters
from zmpkit.compensate.summary import CompensationSummary, summary_of
from zmpkit.compensate.tuning import TuningResult, prior_from_offset, tune_offset
from zmpkit.errors import ParameterError
from zmpkit.experiments import MAX_WORKERS
from zmpkit.experiments.walk_config import (
    CLAMPED_SPEED_FACTOR,
    STEP_DURATION_RANGE_S,
    max_walk_speed_mps,
)
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.robots.robot import DEFAULT_WALK_SPEED_MPS, Robot
from zmpkit.robots.truth_variant import scaled_truth_file
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking import generate_pattern
from zmpkit.walking.walk_controllers import CONTROLLERS

__all__ = [
    "METHODS",
    "CompensateConfig",
    "CompensateProgress",
    "CompensateResult",
    "run_walk_compensate",
]

METHODS: tuple[str, ...] = ("alg1", "alg2", *OFFSET_SHAPES, "auto")
"""Values of ``--method``."""
QUICK_DURATION_S = 6.0
"""Walking time of every walk with ``--quick`` [s]."""
FULL_DURATION_S = 10.0
"""Walking time of every walk otherwise [s] (paper B's 10 s)."""
QUICK_EVALUATIONS, FULL_EVALUATIONS = 4, 16
"""Tuning candidates per shape after the prior, with and without ``--quick`` [-]."""
VALIDATION_SPEEDS_MPS = (0.15, 0.25)
"""Open loop: speeds of the validation walks besides the tuning speed, for a robot walking at
0.2 m/s (times :attr:`CompensateConfig.speed_scale`) [m/s]."""
TUNING_SPEED_CHANGE_MPS = -0.05
"""With feedback: the slower tuning walks' speed change, at a walking speed of 0.2 m/s
(times :attr:`CompensateConfig.speed_scale`) [m/s]."""
TUNING_STEP_CHANGE_S = -0.05
"""With feedback: the shorter tuning walks' step-duration change [s]."""
MIN_HELD_OUT_SPEED_MPS = 0.05
"""With feedback: the slowest validation walk, at a walking speed of 0.2 m/s (times
:attr:`CompensateConfig.speed_scale`) [m/s]."""
HELD_OUT_WALKS: tuple[tuple[float, float, float], ...] = (
    (+0.05, +0.05, 1.3), (-0.08, -0.10, 0.7), (+0.02, -0.08, 0.85), (-0.03, +0.08, 1.15),
)  # fmt: skip
"""With feedback, the validation walks: (speed change at a walking speed of 0.2 m/s, times
:attr:`CompensateConfig.speed_scale` [m/s], step-duration change [s], gear stiffness factor
[-]) from the tuning walk; each differs from every tuning walk in speed, step duration and
robot. ``--quick`` keeps the first two."""
TRUTH_PARAMETER = "gear.stiffness"
"""The truth value the held-out robots vary."""

CompensateProgress = Callable[[str, int, int], None]
"""``progress(stage, finished, total)``."""


@dataclass(frozen=True)
class CompensateConfig:
    """One ``zmpkit walk compensate`` run.

    Attributes:
        method: one of :data:`METHODS`.
        robot: the walking robot; a registry name or ``robot.yaml`` path is resolved once,
            on creation.
        quick: short walks and a small tuning budget (< 5 min on 2 cores).
        speed_mps: speed of the tuning walk [m/s]; None: the robot's walking speed
            (:attr:`~zmpkit.robots.robot.WalkingDefaults.speed_mps`).
        step_duration_s: step duration [s] (the offsets' period).
        effects: effects of the simulated robot (``"all"`` by default).
        seed: noise seed of the tuning walk; validation uses other seeds.
        workers: processes of the pool.
        iterations: iterations of Algorithm 1.
        bias_gain: α1 of Algorithm 2.
        smoothing_gain: α2 of Algorithm 2.
        evaluations: tuning candidates per shape, or None for the default of ``quick``.
        cache_dir: folder of cached walks, or None for ``OUT/cache``.
        figures: whether to draw the figures.
        controller: the walking controller of every walk. ``open`` keeps paper B's
            simulation: tuned on one walk, validated on other seeds and speeds. With feedback
            (``zmpip``, ``dcm``) tuning scores every candidate on several walks (two speeds,
            two step durations; a fall is a failure) and validation walks differ from all of
            them in speed, step duration and robot (:data:`HELD_OUT_WALKS`).
    """

    method: str = "auto"
    robot: Robot = field(default_factory=lambda: get_robot(DEFAULT_WALK_ROBOT))
    quick: bool = False
    speed_mps: float | None = None
    step_duration_s: float = 0.5
    effects: str = "all"
    seed: int = 0
    workers: int = 2
    iterations: int = 10
    bias_gain: float = 0.99
    smoothing_gain: float = 0.95
    evaluations: int | None = None
    cache_dir: str | None = None
    figures: bool = True
    controller: str = "open"

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ParameterError(f"method must be one of {', '.join(METHODS)}; got {self.method!r}")
        object.__setattr__(self, "robot", get_robot(self.robot, needs="walking"))
        walking = self.robot.require_walking()
        if self.speed_mps is None:
            object.__setattr__(self, "speed_mps", walking.speed_mps)
        _validate.in_range(
            "CompensateConfig.step_duration_s", self.step_duration_s, *STEP_DURATION_RANGE_S, "s"
        )
        fastest = max_walk_speed_mps(self.step_duration_s, walking.max_step_length_m)
        limit = round(CLAMPED_SPEED_FACTOR * fastest, 6)
        speed = _validate.finite("CompensateConfig.speed_mps", self.tuning_speed_mps)
        if not 0.0 < speed <= limit:
            raise ParameterError(
                f"CompensateConfig.speed_mps must lie in (0, {limit:g}] m/s, "
                f"got {self.speed_mps:g} m/s"
            )
        if not 1 <= self.workers <= MAX_WORKERS:
            raise ParameterError(
                f"CompensateConfig.workers must lie in [1, {MAX_WORKERS}]; got {self.workers}"
            )
        for name in ("workers", "iterations"):
            if getattr(self, name) < 1:
                raise ParameterError(
                    f"CompensateConfig.{name} must be >= 1; got {getattr(self, name)}"
                )
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)
        self.algorithm2_parameters()
        if self.controller not in CONTROLLERS:
            raise ParameterError(
                f"controller must be one of {', '.join(CONTROLLERS)}; got {self.controller!r}"
            )
        if self.method == "alg2" and self.controller not in ("open", "zmpip"):
            raise ParameterError(
                f"method alg2 adapts the ZMP reference of a preview controller: run it with "
                f"controller zmpip (paper B's) or open; got {self.controller!r}"
            )
        self._check_held_out_speed()
        self._check_walks()

    def _check_held_out_speed(self) -> None:
        if not self.held_out:
            return
        change = -min(dv for dv, _, _ in self._held_out_cases()) * self.speed_scale
        slowest = MIN_HELD_OUT_SPEED_MPS * self.speed_scale
        if round(self.tuning_speed_mps - change, 6) < round(slowest, 6):
            least = round(slowest + change, 6)
            raise ParameterError(
                f"speed_mps must be >= {least:g} m/s with feedback (held-out walks go "
                f"{change:g} m/s slower); got {self.speed_mps}"
            )

    def _check_walks(self) -> None:
        for walk in (*self.tuning_walks(), *self.validation_walks()):
            try:
                walk.walk_config()
            except ParameterError as error:
                raise ParameterError(f"the walk {walk.label}: {error}") from None

    @property
    def tuning_speed_mps(self) -> float:
        """Speed of the tuning walk [m/s]: ``speed_mps``, the robot's walking speed if None."""
        assert self.speed_mps is not None  # set in __post_init__
        return self.speed_mps

    @property
    def speed_scale(self) -> float:
        """The robot's walking speed over paper B's 0.2 m/s [-].

        It scales the speeds and speed changes of the tuning and validation walks (module
        docstring): 1 for a robot that walks at 0.2 m/s.
        """
        walking = self.robot.require_walking()
        return walking.speed_mps / DEFAULT_WALK_SPEED_MPS

    @property
    def duration_s(self) -> float:
        """Walking time of every walk [s]."""
        return QUICK_DURATION_S if self.quick else FULL_DURATION_S

    @property
    def tuning_evaluations(self) -> int:
        """Tuning candidates per shape after the prior [-]."""
        if self.evaluations is not None:
            return self.evaluations
        return QUICK_EVALUATIONS if self.quick else FULL_EVALUATIONS

    def algorithm2_parameters(self) -> Algorithm2Parameters:
        """α1 and α2 of Algorithm 2."""
        return Algorithm2Parameters(self.bias_gain, self.smoothing_gain)

    @property
    def held_out(self) -> bool:
        """Whether tuning and validation follow the held-out design (feedback walks)."""
        return self.controller != "open"

    def _walk(
        self, speed: float, step: float, seed: int, truth: str | None = None,
        truth_label: str = "",
    ) -> WalkSpec:  # fmt: skip
        return WalkSpec(
            speed,
            seed,
            self.duration_s,
            self.effects,
            step,
            self.controller,
            truth,
            truth_label,
            robot=self.robot,
        )

    def tuning_walks(self) -> tuple[WalkSpec, ...]:
        """The walks the offsets are tuned on.

        Open loop: the one walk at ``speed_mps``. With feedback: ``speed_mps`` and 0.05 m/s
        slower (times :attr:`speed_scale`), ``step_duration_s`` and 0.05 s shorter
        (``--quick``: the two diagonal ones).
        """
        v, t, s = self.tuning_speed_mps, self.step_duration_s, self.seed
        if not self.held_out:
            return (self._walk(v, t, s),)
        slower, shorter = v + TUNING_SPEED_CHANGE_MPS * self.speed_scale, t + TUNING_STEP_CHANGE_S
        pairs = [(v, t), (slower, shorter)]
        if not self.quick:
            pairs += [(slower, t), (v, shorter)]
        return tuple(self._walk(round(v_, 6), round(t_, 6), s) for v_, t_ in pairs)

    def _held_out_cases(self) -> tuple[tuple[float, float, float], ...]:
        return HELD_OUT_WALKS[:2] if self.quick else HELD_OUT_WALKS

    def validation_walks(self, truth_folder: Path | None = None) -> tuple[WalkSpec, ...]:
        """Walks never used for tuning (class docstring).

        Args:
            truth_folder: where the held-out robots' truth files are written (feedback walks
                only); None: the shipped robot (for counting the walks).
        """
        if self.held_out:
            robot = self.robot
            walks = []
            for k, (dv, dt, factor) in enumerate(self._held_out_cases()):
                truth = None
                if truth_folder is not None:
                    truth = str(scaled_truth_file(robot, TRUTH_PARAMETER, factor, truth_folder))
                label = f"{TRUTH_PARAMETER} x{factor:g}"
                speed = round(self.tuning_speed_mps + dv * self.speed_scale, 6)
                step = round(self.step_duration_s + dt, 6)
                walks.append(
                    self._walk(speed, step, self.seed + k + 1, truth=truth, truth_label=label)
                )
            return tuple(walks)
        d, e, s, r = self.duration_s, self.effects, self.seed, self.robot
        t = self.step_duration_s
        speeds = [round(v * self.speed_scale, 6) for v in VALIDATION_SPEEDS_MPS]
        other = [WalkSpec(v, s + 1, d, e, t, robot=r) for v in speeds]
        if self.quick:
            return tuple(other)
        v = self.tuning_speed_mps
        return (WalkSpec(v, s + 1, d, e, t, robot=r), WalkSpec(v, s + 2, d, e, t, robot=r), *other)


@dataclass(frozen=True)
class CompensateResult:
    """What a compensation run produced.

    Attributes:
        config: what was asked.
        summary: what ``summary.json`` holds.
        chosen: the method or shape whose numbers the summary reports.
        baseline: the validation walks without compensation.
        compensated: method or shape -> its validation walks.
        tuning: shape -> tuning result (offset methods only).
        files: every file written, by role (empty until
            :func:`~zmpkit.pipelines.walk_compensate_report.write_walk_compensate`).
        started_s: when the run started [s since the epoch].
    """

    config: CompensateConfig
    summary: CompensationSummary
    chosen: str
    baseline: tuple[CompensatedWalk, ...]
    compensated: dict[str, tuple[CompensatedWalk, ...]]
    tuning: dict[str, TuningResult] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)


def _pool_map(jobs: list[tuple[Callable, tuple]], workers: int) -> list[CompensatedWalk]:
    if workers <= 1:
        return [function(*args) for function, args in jobs]
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(function, *args) for function, args in jobs]
        return [f.result() for f in futures]


def _tune_shapes(config: CompensateConfig, cache: Path, report) -> dict[str, TuningResult]:
    shapes = OFFSET_SHAPES if config.method == "auto" else (config.method,)
    walk = config.tuning_walks()[0].walk_config()
    pattern = generate_pattern(walk.pattern_config())
    robot = config.robot
    model_offset = compensate_abstraction(
        walk.pattern_config(), robot.ik_model(), config.iterations, ik_settings=robot.ik_settings
    )
    results = {}
    for i, shape in enumerate(shapes):
        report(f"tuning {shape}", i, len(shapes))
        prior = prior_from_offset(shape, model_offset.zmp_offset_in_world, pattern)
        results[shape] = tune_offset(prior, config.tuning_walks(), config.tuning_evaluations,
                                     cache, config.workers, config.seed)  # fmt: skip
    return results


def _validation_jobs(
    config: CompensateConfig, offsets: dict[str, OffsetParameters], walks: tuple[WalkSpec, ...]
):
    jobs: list[tuple[Callable, tuple]] = [(walk_with_offset, (w, None)) for w in walks]
    if config.method == "alg1":
        jobs += [(walk_with_algorithm1, (w, config.iterations)) for w in walks]
        return jobs, ["alg1"]
    if config.method == "alg2":
        jobs += [(walk_with_algorithm2, (w, config.algorithm2_parameters())) for w in walks]
        return jobs, ["alg2"]
    for offset in offsets.values():
        jobs += [(walk_with_offset, (w, offset)) for w in walks]
    return jobs, list(offsets)


def run_walk_compensate(
    config: CompensateConfig, out_dir: str | Path, progress: CompensateProgress | None = None
) -> CompensateResult:
    """Compensate the walking robot's walk with ``config.method``.

    Tuning walks are cached under ``out_dir/cache`` (or ``config.cache_dir``) as they finish,
    so a rerun resumes; the results are written by
    :func:`~zmpkit.pipelines.walk_compensate_report.write_walk_compensate`.

    Args:
        config: the run.
        out_dir: output folder of the run (created if missing).
        progress: called with (stage, finished, total) as stages finish.

    Returns:
        The summary, the validation walks and the tuning.
    """
    started_s = time.time()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cache = Path(config.cache_dir) if config.cache_dir else out / "cache"
    report = progress or (lambda stage, done, total: None)
    tuning = (
        _tune_shapes(config, cache, report) if config.method in (*OFFSET_SHAPES, "auto") else {}
    )
    offsets = {shape: result.best for shape, result in tuning.items()}
    walks_out = config.validation_walks(cache / "held_out_robots")
    jobs, labels = _validation_jobs(config, offsets, walks_out)
    report("validation walks", 0, len(jobs))
    walks = _pool_map(jobs, config.workers)
    report("validation walks", len(jobs), len(jobs))
    n = len(walks_out)
    baseline = tuple(walks[:n])
    compensated = {label: tuple(walks[n * (i + 1) : n * (i + 2)]) for i, label in enumerate(labels)}
    chosen = min(tuning, key=lambda s: tuning[s].best_objective) if tuning else labels[0]
    summary = summary_of(config.method, baseline, compensated[chosen])
    return CompensateResult(
        config, summary, chosen, baseline, compensated, tuning, started_s=started_s
    )
