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

The planner's inputs live in :mod:`zmpkit.walking.gait`, its result in
:mod:`zmpkit.walking.footstep_plan`; both are re-exported here.
"""

from __future__ import annotations

import math

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.footstep_plan import Footstep, FootstepPlan, SupportPhase
from zmpkit.walking.gait import (
    SIDE_SIGN,
    VALID_SIDES,
    FootShape,
    GaitParameters,
    Side,
    StepLimits,
    WalkCommand,
)

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
