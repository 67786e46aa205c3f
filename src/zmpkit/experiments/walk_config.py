"""The configuration of one walk experiment: the command, the gait and the simulated robot."""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_trial import Push, SensorFault
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand
from zmpkit.walking.gait import FootShape, StepLimits
from zmpkit.walking.walk_controllers import CONTROLLERS

__all__ = ["WalkConfig"]


@dataclass(frozen=True)
class WalkConfig:
    """One walk, as ``zmpkit walk`` takes it.

    Attributes:
        robot: the robot's registry name or ``robot.yaml`` path (it needs walking defaults).
        speed_mps: commanded forward speed [m/s].
        step_duration_s: one step [s].
        duration_s: walking time [s] (plus standing before and after).
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
    """

    robot: str = DEFAULT_WALK_ROBOT
    speed_mps: float = 0.2
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

    def __post_init__(self) -> None:
        walking = get_robot(self.robot, needs="walking").require_walking()
        if self.com_height_m is None:
            object.__setattr__(self, "com_height_m", walking.com_height_m)
        _validate.finite("WalkConfig.speed_mps", self.speed_mps)
        _validate.finite("WalkConfig.lateral_speed_mps", self.lateral_speed_mps)
        _validate.finite("WalkConfig.turn_rate_rps", self.turn_rate_rps)
        if self.controller not in CONTROLLERS:
            raise ParameterError(
                f"controller must be one of {', '.join(CONTROLLERS)}; got {self.controller!r}"
            )
        object.__setattr__(self, "pushes", tuple(self.pushes))
        object.__setattr__(self, "faults", tuple(self.faults))
        _validate.positive("WalkConfig.step_duration_s", self.step_duration_s, "s")
        _validate.positive("WalkConfig.duration_s", self.duration_s, "s")
        _validate.positive("WalkConfig.com_height_m", self.com_height_m or 0.0, "m")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"WalkConfig.seed must be an integer >= 0; got {self.seed!r}")
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)

    def pattern_config(self) -> PatternConfig:
        """The walking pattern this walk plays, with the robot's walking defaults.

        The robot gives the foot separation, the step length limit, the sole and the motion
        frame (:class:`~zmpkit.robots.robot.WalkingDefaults`).
        """
        walking = get_robot(self.robot, needs="walking").require_walking()
        length, width = walking.sole_size_m
        return PatternConfig(
            command=WalkCommand(
                v_x=self.speed_mps, v_y=self.lateral_speed_mps, omega=self.turn_rate_rps
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
        )
