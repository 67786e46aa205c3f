"""The configuration of one walk experiment: the command, the gait and the simulated robot."""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.robots.nao import NAO_WALK_COM_HEIGHT_M
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking import GaitParameters, PatternConfig, StepLimits, WalkCommand

__all__ = [
    "MAX_WALK_DURATION_S",
    "ROBOTS",
    "STEP_DURATION_RANGE_S",
    "WalkConfig",
    "max_walk_speed_mps",
]

ROBOTS: tuple[str, ...] = ("nao",)
"""Robots that can walk."""
STEP_DURATION_RANGE_S = (0.2, 2.0)
"""Step durations a walk takes [s]: NAO's fastest steps to a slow, deliberate gait."""
MAX_WALK_DURATION_S = 3600.0
"""Longest walking time [s]."""


def max_walk_speed_mps(step_duration_s: float, limits: StepLimits | None = None) -> float:
    """Fastest forward speed [m/s]: the longest step (``limits``) once per step duration [s].

    A step of a walk at ``v`` [m/s] lands ``v * T`` ahead of the stance foot; beyond
    ``max_step_length_m / T`` the planner would clamp every step and the robot would not walk
    at the commanded speed.
    """
    return (limits or StepLimits()).max_step_length_m / step_duration_s


@dataclass(frozen=True)
class WalkConfig:
    """One walk, as ``zmpkit walk`` takes it.

    Attributes:
        robot: robot name, one of :data:`ROBOTS`.
        speed_mps: commanded forward speed [m/s], from 0 to :func:`max_walk_speed_mps`.
        step_duration_s: one step [s], in :data:`STEP_DURATION_RANGE_S`.
        duration_s: walking time [s] (plus standing before and after), from one step to
            :data:`MAX_WALK_DURATION_S`.
        effects: ``"all"``, ``"none"`` or letters such as ``"M,I,G,F"``.
        seed: seed of the sensor noise.
        com_height_m: CoM height of the pattern [m].
        truth: a truth file for the simulator, or None for the shipped one.
        figures: whether to draw the figures.
    """

    robot: str = "nao"
    speed_mps: float = 0.2
    step_duration_s: float = 0.5
    duration_s: float = 10.0
    effects: str = "all"
    seed: int = 0
    com_height_m: float = NAO_WALK_COM_HEIGHT_M
    truth: str | None = None
    figures: bool = True

    def __post_init__(self) -> None:
        if self.robot not in ROBOTS:
            raise ParameterError(f"robot must be one of {', '.join(ROBOTS)}; got {self.robot!r}")
        _validate.in_range(
            "WalkConfig.step_duration_s", self.step_duration_s, *STEP_DURATION_RANGE_S, "s"
        )
        fastest = round(max_walk_speed_mps(self.step_duration_s), 6)
        _validate.in_range("WalkConfig.speed_mps (forward)", self.speed_mps, 0.0, fastest, "m/s")
        _validate.in_range(
            "WalkConfig.duration_s", self.duration_s, self.step_duration_s, MAX_WALK_DURATION_S, "s"
        )
        _validate.positive("WalkConfig.com_height_m", self.com_height_m, "m")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"WalkConfig.seed must be an integer >= 0; got {self.seed!r}")
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)

    def pattern_config(self) -> PatternConfig:
        """The walking pattern this walk plays."""
        return PatternConfig(
            command=WalkCommand(v_x=self.speed_mps),
            duration_s=self.duration_s,
            gait=GaitParameters(step_duration_s=self.step_duration_s),
            com_height_m=self.com_height_m,
        )
