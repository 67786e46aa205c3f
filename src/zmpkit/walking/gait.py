"""Inputs of the footstep planner: walking command, gait timing, sole shape and step limits.

Frames: the gait (mid-feet) frame has x forward, y left, z up; step limits are expressed in
the stance-foot frame. Lengths in [m], angles in [rad], times in [s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from zmpkit import _validate

__all__ = [
    "SIDE_SIGN",
    "VALID_SIDES",
    "FootShape",
    "GaitParameters",
    "Side",
    "StepLimits",
    "WalkCommand",
]

#: A foot: "left" or "right".
Side = Literal["left", "right"]

#: Sign of the lateral axis (y) pointing from the body centre to each foot.
SIDE_SIGN: dict[str, float] = {"left": 1.0, "right": -1.0}
#: Sides a footstep can have.
VALID_SIDES = ("left", "right")


@dataclass(frozen=True)
class WalkCommand:
    """Commanded walking velocity in the gait (mid-feet) frame.

    Attributes:
        v_x: forward velocity [m/s].
        v_y: leftward velocity [m/s].
        omega: yaw rate, counter-clockwise positive [rad/s].
    """

    v_x: float = 0.2
    v_y: float = 0.0
    omega: float = 0.0

    def __post_init__(self) -> None:
        for name in ("v_x", "v_y", "omega"):
            _validate.finite(f"WalkCommand.{name}", getattr(self, name))


@dataclass(frozen=True)
class GaitParameters:
    """Timing and nominal geometry of the gait.

    Attributes:
        step_duration_s: one step, double support then single support [s].
        double_support_ratio: share of a step spent in double support [-], in [0, 0.9].
        foot_separation_m: nominal lateral distance between the foot centres [m]
            (paper B's robot: hips at y = +-0.050 m, so 0.100 m).
        initial_double_support_s: standing time with the ZMP centred before the first
            weight transfer [s].
        final_double_support_s: standing time with the ZMP centred after the last weight
            transfer [s].
    """

    step_duration_s: float = 0.5
    double_support_ratio: float = 0.2
    foot_separation_m: float = 0.100
    initial_double_support_s: float = 1.0
    final_double_support_s: float = 1.5

    def __post_init__(self) -> None:
        _validate.positive("GaitParameters.step_duration_s", self.step_duration_s, "s")
        _validate.in_range("GaitParameters.double_support_ratio", self.double_support_ratio, 0, 0.9)
        _validate.positive("GaitParameters.foot_separation_m", self.foot_separation_m, "m")
        _validate.non_negative(
            "GaitParameters.initial_double_support_s", self.initial_double_support_s, "s"
        )
        _validate.non_negative(
            "GaitParameters.final_double_support_s", self.final_double_support_s, "s"
        )

    @property
    def double_support_s(self) -> float:
        """Double-support time of one step [s]."""
        return self.step_duration_s * self.double_support_ratio

    @property
    def single_support_s(self) -> float:
        """Single-support (swing) time of one step [s]."""
        return self.step_duration_s - self.double_support_s


@dataclass(frozen=True)
class FootShape:
    """Sole rectangle centred on the footstep position.

    Defaults: 0.16 x 0.09 m, paper B's robot's 158 x 88 mm outline rounded up.

    Attributes:
        length_m: along the foot's x axis [m].
        width_m: along the foot's y axis [m].
    """

    length_m: float = 0.16
    width_m: float = 0.09

    def __post_init__(self) -> None:
        _validate.positive("FootShape.length_m", self.length_m, "m")
        _validate.positive("FootShape.width_m", self.width_m, "m")

    def corners_in_foot(self) -> tuple[tuple[float, float], ...]:
        """The four sole corners in the foot frame [m], counter-clockwise."""
        hx, hy = self.length_m / 2, self.width_m / 2
        return ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))


@dataclass(frozen=True)
class StepLimits:
    """Limits on one step, relative to the stance foot, in the stance-foot frame.

    Attributes:
        max_step_length_m: largest |x| of the landing foot [m].
        max_step_width_m: largest lateral opening beyond the nominal separation [m].
        max_turn_rad: largest |yaw| of the landing foot [rad].
        min_foot_clearance_m: smallest lateral gap between the soles [m]; every corner of
            the landing sole stays at least this far beyond the stance sole's inner edge.
        foot: sole geometry used for the clearance.
    """

    max_step_length_m: float = 0.12
    max_step_width_m: float = 0.06
    max_turn_rad: float = 0.4
    min_foot_clearance_m: float = 0.005
    foot: FootShape = FootShape()

    def __post_init__(self) -> None:
        _validate.positive("StepLimits.max_step_length_m", self.max_step_length_m, "m")
        _validate.non_negative("StepLimits.max_step_width_m", self.max_step_width_m, "m")
        _validate.in_range("StepLimits.max_turn_rad", self.max_turn_rad, 0.0, math.pi / 2, "rad")
        _validate.non_negative("StepLimits.min_foot_clearance_m", self.min_foot_clearance_m, "m")

    @property
    def min_foot_separation_m(self) -> float:
        """Smallest lateral distance between parallel foot centres [m]."""
        return self.foot.width_m + self.min_foot_clearance_m

    def min_lateral_offset_m(self, yaw_rad: float) -> float:
        """Smallest lateral offset of a landing foot turned outward by ``yaw_rad`` [m].

        The stance sole is treated as an infinite strip along its x axis (conservative).
        """
        foot = self.foot
        yaw = abs(yaw_rad)
        return (
            foot.width_m / 2
            + self.min_foot_clearance_m
            + foot.length_m / 2 * math.sin(yaw)
            + foot.width_m / 2 * math.cos(yaw)
        )
