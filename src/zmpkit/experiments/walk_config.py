"""The configuration of one walk experiment: the command, the gait and the simulated robot."""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_disturbances import Push, SensorFault
from zmpkit.robots.robot import Robot
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand
from zmpkit.walking.gait import FootShape, StepLimits
from zmpkit.walking.walk_controllers import CONTROLLERS

__all__ = [
    "CLAMPED_SPEED_FACTOR",
    "MAX_WALK_DURATION_S",
    "STEP_DURATION_RANGE_S",
    "WalkConfig",
    "max_walk_speed_mps",
]

STEP_DURATION_RANGE_S = (0.2, 2.0)
"""Step durations a walk takes [s]: a small robot's fastest steps to a slow, deliberate gait."""
MAX_WALK_DURATION_S = 3600.0
"""Longest walking time [s]."""
CLAMPED_SPEED_FACTOR = 2.0
"""Commands up to this times the fastest unclamped speed are walked with shortened steps (a
warning and ``clamped_step_limits``); faster ones are refused [-]."""


def max_walk_speed_mps(step_duration_s: float, max_step_length_m: float) -> float:
    """Fastest forward speed without clamping [m/s]: the longest step once per step [s].

    A step of a walk at ``v`` [m/s] lands ``v * T`` ahead of the stance foot; beyond
    ``max_step_length_m / T`` the planner shortens every step and the robot walks slower
    than commanded.
    """
    return max_step_length_m / step_duration_s


@dataclass(frozen=True)
class WalkConfig:
    """One walk, as ``zmpkit walk`` takes it.

    Attributes:
        robot: the robot (it needs walking defaults).
        speed_mps: commanded forward speed [m/s], from 0 to :data:`CLAMPED_SPEED_FACTOR` times
            :func:`max_walk_speed_mps` (beyond it once, steps are shortened: a warning); None:
            the robot's walking default (:attr:`~zmpkit.robots.robot.WalkingDefaults.speed_mps`,
            0.2 unless the robot gives its own).
        step_duration_s: one step [s], in :data:`STEP_DURATION_RANGE_S`.
        duration_s: walking time [s] (plus standing before and after), from one step to
            :data:`MAX_WALK_DURATION_S`.
        effects: ``"all"``, ``"none"`` or letters such as ``"M,I,G,F"``.
        seed: seed of the sensor noise.
        com_height_m: CoM height of the pattern [m]; None: the robot's walking default.
        truth: a truth file for the simulator, or None for the shipped one.
        figures: whether to draw the figures.
        controller: the walking controller, one of
            :data:`~zmpkit.walking.walk_controllers.CONTROLLERS`.
        lateral_speed_mps: commanded leftward speed [m/s].
        turn_rate_rps: commanded yaw rate, counter-clockwise positive [rad/s].
        pushes: forces on the torso during the walk.
        faults: sensor faults the controller meets.
        video: whether to record the walk as a video (``walk.mp4``, drawn after the walk
            from its recorded configurations).
        heading_feedback: whether a feedback walk (``zmpip``, ``dcm``) turns its footsteps
            by the IMU's yaw to keep its heading (:mod:`zmpkit.walking.heading_feedback`).
        step_adjustment: whether a feedback walk moves its steps to capture its DCM after a
            push (:mod:`zmpkit.walking.step_adjustment`).
    """

    robot: Robot
    speed_mps: float | None = None
    step_duration_s: float = 0.5
    duration_s: float = 10.0
    effects: str = "all"
    seed: int = 0
    com_height_m: float | None = None
    truth: str | None = None
    figures: bool = True
    controller: str = "open"
    lateral_speed_mps: float = 0.0
    turn_rate_rps: float = 0.0
    pushes: tuple[Push, ...] = ()
    faults: tuple[SensorFault, ...] = ()
    video: bool = False
    heading_feedback: bool = True
    step_adjustment: bool = False

    def __post_init__(self) -> None:
        walking = self.robot.require_walking()
        if self.com_height_m is None:
            object.__setattr__(self, "com_height_m", walking.com_height_m)
        speed = walking.speed_mps if self.speed_mps is None else self.speed_mps
        object.__setattr__(self, "speed_mps", speed)
        _validate.in_range(
            "WalkConfig.step_duration_s", self.step_duration_s, *STEP_DURATION_RANGE_S, "s"
        )
        fastest = max_walk_speed_mps(self.step_duration_s, walking.max_step_length_m)
        limit = round(CLAMPED_SPEED_FACTOR * fastest, 6)
        _validate.in_range("WalkConfig.speed_mps (forward)", speed, 0.0, limit, "m/s")
        _validate.in_range(
            "WalkConfig.lateral_speed_mps", self.lateral_speed_mps, -limit, limit, "m/s"
        )
        _validate.in_range("WalkConfig.turn_rate_rps", self.turn_rate_rps, -2.0, 2.0, "rad/s")
        _validate.in_range(
            "WalkConfig.duration_s", self.duration_s, self.step_duration_s, MAX_WALK_DURATION_S, "s"
        )
        if self.controller not in CONTROLLERS:
            raise ParameterError(
                f"controller must be one of {', '.join(CONTROLLERS)}; got {self.controller!r}"
            )
        object.__setattr__(self, "pushes", tuple(self.pushes))
        object.__setattr__(self, "faults", tuple(self.faults))
        _validate.positive("WalkConfig.com_height_m", self.com_height_m or 0.0, "m")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"WalkConfig.seed must be an integer >= 0; got {self.seed!r}")
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)

    def pattern_config(self) -> PatternConfig:
        """The walking pattern this walk plays, with the robot's walking defaults.

        The robot gives the foot separation, the step length limit, the sole and the motion
        frame (:class:`~zmpkit.robots.robot.WalkingDefaults`).
        """
        walking = self.robot.require_walking()
        length, width = walking.sole_size_m
        return PatternConfig(
            command=WalkCommand(
                v_x=self.speed_mps,  # type: ignore[arg-type]  # set in __post_init__
                v_y=self.lateral_speed_mps,
                omega=self.turn_rate_rps,
            ),
            duration_s=self.duration_s,
            gait=GaitParameters(
                step_duration_s=self.step_duration_s,
                foot_separation_m=walking.foot_separation_m,
            ),
            limits=StepLimits(
                max_step_length_m=walking.max_step_length_m, foot=FootShape(length, width)
            ),
            control_period_s=walking.control_period_s,
            com_height_m=self.com_height_m,  # type: ignore[arg-type]  # set in __post_init__
            zmp_forward_m=walking.zmp_forward_m,
        )
