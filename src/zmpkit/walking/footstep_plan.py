"""The planner's result: a timed footstep sequence and its support phases.

A footstep's ``(x, y)`` is the centre of its sole rectangle in the world frame [m], its
``yaw`` the sole's heading about z [rad], unwrapped. Support phases alternate double and
single support and cover the plan from the initial to the final standstill [s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from zmpkit.errors import ParameterError
from zmpkit.walking.gait import VALID_SIDES, GaitParameters, Side

__all__ = ["Footstep", "FootstepPlan", "SupportPhase"]


@dataclass(frozen=True)
class Footstep:
    """One foot placement and the swing that leads to it.

    Attributes:
        index: 0-based step number; -1 marks a foot's initial placement.
        side: "left" or "right".
        x: sole centre, world frame [m].
        y: sole centre, world frame [m].
        yaw: sole heading, world frame, unwrapped [rad].
        t_start: lift-off time of the swing [s] (= t_end for an initial placement).
        t_end: touch-down time [s].
    """

    index: int
    side: Side
    x: float
    y: float
    yaw: float
    t_start: float
    t_end: float

    def __post_init__(self) -> None:
        if self.side not in VALID_SIDES:
            raise ParameterError(f"Footstep.side must be one of {VALID_SIDES}, got {self.side!r}")
        if self.t_end < self.t_start:
            raise ParameterError(
                f"Footstep.t_end must be >= t_start = {self.t_start} s, got {self.t_end} s"
            )

    def to_local(self, x: float, y: float) -> tuple[float, float]:
        """Express the world point ``(x, y)`` [m] in this foot's frame [m]."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        dx, dy = x - self.x, y - self.y
        return c * dx + s * dy, -s * dx + c * dy


@dataclass(frozen=True)
class SupportPhase:
    """A time interval with one or both feet on the ground.

    Attributes:
        kind: "double" or "single".
        t_start: start [s].
        t_end: end [s].
        stance_side: the supporting foot in single support, None in double support.
        step_index: the step whose swing (single) or preceding weight transfer (double)
            this is; -1 for the initial standstill, len(steps) for the final transfer.
    """

    kind: Literal["double", "single"]
    t_start: float
    t_end: float
    stance_side: Side | None
    step_index: int


@dataclass(frozen=True)
class FootstepPlan:
    """A timed footstep sequence.

    Attributes:
        steps: the moving steps, alternating sides, index 0..n-1.
        initial_left: left foot before the walk (index -1).
        initial_right: right foot before the walk (index -1).
        gait: the timing and separation used.
        clamped_limits: names of the limits that changed any step ("step_length",
            "step_width", "turn", "foot_clearance"); empty when the command fitted.
    """

    steps: tuple[Footstep, ...]
    initial_left: Footstep
    initial_right: Footstep
    gait: GaitParameters
    clamped_limits: tuple[str, ...] = ()

    @property
    def was_clamped(self) -> bool:
        """True when a limit changed at least one step."""
        return bool(self.clamped_limits)

    @property
    def walk_start_s(self) -> float:
        """Start of the first weight transfer [s]."""
        return self.gait.initial_double_support_s

    @property
    def duration_s(self) -> float:
        """Whole plan, initial standstill to the end of the final standstill [s]."""
        g = self.gait
        walk_end = self.walk_start_s + len(self.steps) * g.step_duration_s
        return walk_end + g.double_support_s + g.final_double_support_s

    def stance_before(self, k: int) -> Footstep:
        """The stance foot during the swing of step ``k`` (the other foot's last placement)."""
        if k > 0:
            return self.steps[k - 1]
        return self.initial_right if self.steps[0].side == "left" else self.initial_left

    def final_feet(self) -> tuple[Footstep, Footstep]:
        """The last placements of the (left, right) feet."""
        last = {"left": self.initial_left, "right": self.initial_right}
        for step in self.steps:
            last[step.side] = step
        return last["left"], last["right"]

    def phases(self) -> tuple[SupportPhase, ...]:
        """Double and single support intervals covering [0, duration_s]."""
        phases = [SupportPhase("double", 0.0, self.walk_start_s, None, -1)]
        for k, step in enumerate(self.steps):
            t0 = self.steps[k - 1].t_end if k else self.walk_start_s
            stance: Side = "right" if step.side == "left" else "left"
            phases.append(SupportPhase("double", t0, step.t_start, None, k))
            phases.append(SupportPhase("single", step.t_start, step.t_end, stance, k))
        t_last = self.steps[-1].t_end
        phases.append(SupportPhase("double", t_last, self.duration_s, None, len(self.steps)))
        return tuple(phases)
