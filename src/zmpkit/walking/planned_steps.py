r"""The footstep plan as a control tick reads it: frames, metres and the stance sole's axes.

Each :class:`PlannedStep` holds what the step adjustment (:mod:`zmpkit.walking.step_adjustment`)
needs of one swing without touching the plan's objects in a tick: the motion frames of its
lift-off and touchdown (from the sampled feet, :func:`~zmpkit.walking.swing.swing_edges`), the
stance and landing soles in the world, and the landing in the stance sole's frame — ``along``
its heading and ``lateral`` outwards, towards the swing foot's side:

.. math:: \begin{bmatrix} Δx \\ l \end{bmatrix} = \begin{bmatrix} \cos ψ & \sin ψ \\
    -s \sin ψ & s \cos ψ \end{bmatrix} (U - S), \qquad s = +1 \text{ (left swing)},
    -1 \text{ (right)},

``ψ`` the stance sole's yaw, ``U`` the landing and ``S`` the stance sole [m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit.walking.gait import SIDE_SIGN
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.swing import swing_edges

__all__ = ["PlannedStep", "planned_steps"]


@dataclass(frozen=True)
class PlannedStep:
    """One swing of the plan (module docstring).

    Attributes:
        side: the swing foot.
        foot: its index in the feet's order [-].
        stance: the stance foot's index [-].
        lift: the last frame on the ground before the swing [-].
        touchdown: the planned touchdown, the first frame on the ground again [-].
        stance_x: the stance sole's centre (x), world frame [m].
        stance_y: the same (y) [m].
        cos_yaw: cos ψ of the stance sole [-].
        sin_yaw: sin ψ [-].
        land_x: the planned landing (x), world frame [m].
        land_y: the same (y) [m].
        along: the landing along the stance sole [m].
        lateral: the landing outwards from the stance sole [m].
        sign: s, +1 for a left swing, -1 for a right one [-].
    """

    side: str
    foot: int
    stance: int
    lift: int
    touchdown: int
    stance_x: float
    stance_y: float
    cos_yaw: float
    sin_yaw: float
    land_x: float
    land_y: float
    along: float
    lateral: float
    sign: float


def planned_steps(pattern: WalkingPattern, feet: tuple[str, ...]) -> tuple[PlannedStep, ...]:
    """The plan's steps whose swing lies in the sampled walk, in order.

    Args:
        pattern: the planned walk.
        feet: the feet's order (the state estimator's).
    """
    plan = pattern.footsteps
    swings = {f: sorted(swing_edges(getattr(pattern.feet, f).in_contact).items()) for f in feet}
    seen = dict.fromkeys(feet, 0)
    steps = []
    for j, step in enumerate(plan.steps):
        if seen[step.side] >= len(swings[step.side]):
            break
        lift, land = swings[step.side][seen[step.side]]
        seen[step.side] += 1
        stance = plan.stance_before(j)
        c, s = math.cos(stance.yaw), math.sin(stance.yaw)
        dx, dy = step.x - stance.x, step.y - stance.y
        sign = SIDE_SIGN[step.side]
        steps.append(PlannedStep(
            step.side, feet.index(step.side), feet.index(stance.side), lift - 1, land,
            stance.x, stance.y, c, s, step.x, step.y, c * dx + s * dy,
            sign * (-s * dx + c * dy), sign,
        ))  # fmt: skip
    return tuple(steps)
