"""Footstep planner: a commanded walking velocity becomes a timed sequence of footsteps.

Frames: the world frame has x forward, y left, z up at the start; the walk starts with both
feet parallel, centred on the world origin, yaw 0. A footstep's ``(x, y)`` is the centre of
its sole rectangle on the ground [m], its ``yaw`` the sole's heading about z [rad], unwrapped
(continuous over the walk, never reduced to (-pi, pi]).

Each step is planned relative to the current stance foot. The command ``(v_x, v_y, omega)``
gives a per-step displacement ``(v_x T, v_y T, omega T)`` of a gait frame midway between the
feet (``T`` the step duration). Sideways and turning motion is taken only on steps of the
*leading* foot (the left foot when walking or turning left), twice as large; the following
step of the other foot closes to the nominal separation, parallel. The feet never cross and
the trailing foot never turns inward relative to its stance foot. The walk starts with a
half-length step and stops with a step that puts the feet together, parallel, at the
nominal separation. Displacement of the mid-feet point for a straight walk of ``n`` steps:
``v_x T (n - 3/2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from zmpkit import _validate
from zmpkit.errors import ParameterError

__all__ = [
    "FootShape",
    "Footstep",
    "FootstepPlan",
    "GaitParameters",
    "Side",
    "StepLimits",
    "SupportPhase",
    "WalkCommand",
    "plan_footsteps",
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
            (NAO: hips at y = +-0.050 m, so 0.100 m).
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

    Defaults: 0.16 x 0.09 m, NAO's 158 x 88 mm outline rounded up (nao-parameters.md §5).

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
            stance = "right" if step.side == "left" else "left"
            phases.append(SupportPhase("double", t0, step.t_start, None, k))
            phases.append(SupportPhase("single", step.t_start, step.t_end, stance, k))
        t_last = self.steps[-1].t_end
        phases.append(SupportPhase("double", t_last, self.duration_s, None, len(self.steps)))
        return tuple(phases)


def plan_footsteps(
    command: WalkCommand,
    gait: GaitParameters | None = None,
    limits: StepLimits | None = None,
    *,
    n_steps: int | None = None,
    duration_s: float | None = None,
    first_side: Side | None = None,
) -> FootstepPlan:
    """Plan a walk from standstill to standstill.

    Args:
        command: commanded velocity of the gait frame.
        gait: timing and separation; defaults to :class:`GaitParameters`.
        limits: step limits and sole geometry; defaults to :class:`StepLimits`.
        n_steps: number of steps, the half-length start and the closing step included (>= 2).
        duration_s: walking time instead of ``n_steps`` [s]; ``round(duration_s / T)`` steps.
        first_side: the first swing foot; default the leading side of ``v_y``, else of
            ``omega``, else "left".

    Returns:
        The plan; ``clamped_limits`` names every limit that changed a step.
    """
    gait = gait or GaitParameters()
    limits = limits or StepLimits()
    n = _step_count(gait, n_steps, duration_s)
    _check_geometry(gait, limits)
    side = _first_side(command, first_side)
    s = gait.foot_separation_m
    initial = {
        "left": Footstep(-1, "left", 0.0, s / 2, 0.0, 0.0, 0.0),
        "right": Footstep(-1, "right", 0.0, -s / 2, 0.0, 0.0, 0.0),
    }
    stance = initial[_other(side)]
    steps: list[Footstep] = []
    clamped: set[str] = set()
    for k in range(n):
        relative, hits = _limit_step(_nominal_step(command, gait, side, k, n), side, gait, limits)
        clamped |= hits
        slot_start = gait.initial_double_support_s + k * gait.step_duration_s
        touch_down = gait.initial_double_support_s + (k + 1) * gait.step_duration_s
        lift_off = min(slot_start + gait.double_support_s, touch_down)
        stance = _place(stance, relative, k, side, lift_off, touch_down)
        steps.append(stance)
        side = _other(side)
    return FootstepPlan(
        tuple(steps), initial["left"], initial["right"], gait, tuple(sorted(clamped))
    )


def _other(side: Side) -> Side:
    return "right" if side == "left" else "left"


def _step_count(gait: GaitParameters, n_steps: int | None, duration_s: float | None) -> int:
    if (n_steps is None) == (duration_s is None):
        raise ParameterError(
            f"give exactly one of n_steps or duration_s, got n_steps={n_steps!r}, "
            f"duration_s={duration_s!r}"
        )
    if duration_s is not None:
        duration = _validate.positive("duration_s", duration_s, "s")
        return max(2, round(duration / gait.step_duration_s))
    if isinstance(n_steps, bool) or not isinstance(n_steps, int) or n_steps < 2:
        raise ParameterError(
            f"n_steps must be an integer >= 2 (start and closing step), got {n_steps!r}"
        )
    return n_steps


def _check_geometry(gait: GaitParameters, limits: StepLimits) -> None:
    s = gait.foot_separation_m
    if s < limits.min_foot_separation_m:
        raise ParameterError(
            f"GaitParameters.foot_separation_m must be >= foot width + clearance = "
            f"{limits.min_foot_separation_m:.4f} m, got {s} m"
        )
    widest = limits.min_lateral_offset_m(limits.max_turn_rad)
    if widest > s + limits.max_step_width_m + 1e-12:
        raise ParameterError(
            f"StepLimits.max_step_width_m must be >= {widest - s:.4f} m so that a step turned "
            f"by max_turn_rad = {limits.max_turn_rad} rad clears the stance foot, "
            f"got {limits.max_step_width_m} m"
        )


def _first_side(command: WalkCommand, first_side: Side | None) -> Side:
    if first_side is not None:
        if first_side not in VALID_SIDES:
            raise ParameterError(f"first_side must be one of {VALID_SIDES}, got {first_side!r}")
        return first_side
    for rate in (command.v_y, command.omega):
        if rate != 0.0:
            return "left" if rate > 0.0 else "right"
    return "left"


def _nominal_step(
    command: WalkCommand, gait: GaitParameters, side: Side, k: int, n: int
) -> tuple[float, float, float]:
    """Gait-frame displacement (x [m], y [m], yaw [rad]) that step ``k`` should carry."""
    if k == n - 1:  # closing step: feet together
        return 0.0, 0.0, 0.0
    sign = SIDE_SIGN[side]
    T = gait.step_duration_s
    dx = command.v_x * T * (0.5 if k == 0 else 1.0)
    dy = 2.0 * command.v_y * T if command.v_y * sign > 0.0 else 0.0
    dyaw = 2.0 * command.omega * T if command.omega * sign > 0.0 else 0.0
    return dx, dy, dyaw


def _limit_step(
    nominal: tuple[float, float, float], side: Side, gait: GaitParameters, limits: StepLimits
) -> tuple[tuple[float, float, float], set[str]]:
    """Landing pose relative to the stance foot, within the limits, and the limits hit."""
    dx, dy, dyaw = nominal
    sign, half = SIDE_SIGN[side], gait.foot_separation_m / 2
    hits: set[str] = set()
    yaw = max(-limits.max_turn_rad, min(limits.max_turn_rad, dyaw))
    if yaw != dyaw:
        hits.add("turn")
    x = dx - sign * half * math.sin(yaw)
    if abs(x) > limits.max_step_length_m:
        x = math.copysign(limits.max_step_length_m, x)
        hits.add("step_length")
    lateral = sign * dy + half * (1.0 + math.cos(yaw))  # outward offset from the stance foot
    widest = 2.0 * half + limits.max_step_width_m
    if lateral > widest:
        lateral = widest
        hits.add("step_width")
    narrowest = limits.min_lateral_offset_m(yaw)
    if lateral < narrowest:
        lateral = narrowest
        hits.add("foot_clearance")
    return (x, sign * lateral, yaw), hits


def _place(
    stance: Footstep,
    relative: tuple[float, float, float],
    k: int,
    side: Side,
    t_start: float,
    t_end: float,
) -> Footstep:
    x, y, yaw = relative
    c, s = math.cos(stance.yaw), math.sin(stance.yaw)
    return Footstep(
        k,
        side,
        stance.x + c * x - s * y,
        stance.y + s * x + c * y,
        stance.yaw + yaw,
        t_start,
        t_end,
    )
