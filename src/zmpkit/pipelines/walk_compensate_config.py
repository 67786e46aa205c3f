"""What a ``zmpkit walk compensate`` run is: its method, robot, and tuning and validation walks.

Open loop (paper B's simulation) tunes on one walk and validates on other noise seeds and
other speeds; with feedback (``zmpip``, ``dcm``) tuning scores each candidate on walks at two
speeds and two step durations, and every validation walk differs from all of them in speed,
step duration and robot (:data:`HELD_OUT_WALKS`). The walks were designed for paper B's robot
at its 0.2 m/s (:data:`~zmpkit.robots.robot.DEFAULT_WALK_SPEED_MPS`); on another robot every
speed and speed change is scaled by the robot's walking speed over 0.2 m/s
(:attr:`CompensateConfig.speed_scale`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from zmpkit import _validate
from zmpkit.compensate.algorithm2 import Algorithm2Parameters
from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.compensate.offsets import OFFSET_SHAPES
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
from zmpkit.walking.walk_controllers import CONTROLLERS

__all__ = [
    "FULL_DURATION_S",
    "HELD_OUT_WALKS",
    "METHODS",
    "QUICK_DURATION_S",
    "TRUTH_PARAMETER",
    "VALIDATION_SPEEDS_MPS",
    "CompensateConfig",
]


METHODS: tuple[str, ...] = ("alg1", "alg2", *OFFSET_SHAPES, "auto")
"""Values of ``--method``."""


QUICK_DURATION_S = 6.0
"""Walking time of every walk with ``--quick`` [s]."""


FULL_DURATION_S = 10.0
"""Walking time of every walk otherwise [s] (paper B's 10 s)."""


QUICK_EVALUATIONS = 4
"""Tuning candidates per shape after the prior with ``--quick`` [-]."""


FULL_EVALUATIONS = 16
"""Tuning candidates per shape after the prior otherwise [-]."""


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
