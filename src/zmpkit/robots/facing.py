r"""Which way a humanoid model faces: what its knees, its names and its feet say.

A model states no forward direction; three kinds of evidence show it, each a vote for a sign
along the feet's long horizontal axis (:func:`facing_votes`):

- **knees**: a knee bends one way only (its range reaches much further to one side of the
  straight leg, e.g. 0 to 2.6 rad); flexing it (towards its range's longer side,
  :data:`FLEXION_RAD` or less) folds the leg and carries the foot *backwards*: the foot's
  horizontal shift :math:`\Delta p` points opposite forward. The knee is the hinge midway
  down the leg (:func:`knee_flexion`). Strong: a physical fact.
- **names**: a foot (or the leg it hangs from) named ``left``/``l`` and the other
  ``right``/``r`` (tokens of the body and joint names) put the model's left side at
  :math:`\ell = p_{\mathrm{left}} - p_{\mathrm{right}}`, so forward is
  :math:`\ell \times \hat z`. Strong: the designer's own labels, which the robot file must
  keep (its ``left`` foot is the model's left foot).
- **toes**: the feet reach further ahead of their ankles than behind (toes are longer than
  heels). Weak: many soles are nearly centred under the ankle.

:func:`robot_init <zmpkit.robots.robot_init.guess_robot>` follows the names, else the knees,
else the toes, and is sure only when no vote disagrees and a strong one is cast;
``zmpkit robot check`` checks the knees of the built robot (:func:`knee_flexions`).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FLEXION_RAD",
    "FacingVote",
    "KneeFlexion",
    "decide",
    "facing_votes",
    "knee_flexion",
    "path_to_root",
    "side_from_names",
]

FLEXION_RAD = 0.5
"""How far a knee is flexed to see where its foot goes [rad] (less when its range is shorter)."""
ONE_SIDED = 2.0
"""A joint bends one way when its range reaches this many times further to one side [-]."""
FOLDS_M = 0.01
"""A knee's flexion moves its foot at least this far [m]."""


@dataclass(frozen=True)
class KneeFlexion:
    """A foot's knee, flexed.

    Attributes:
        joint: the knee joint's name.
        flexion_rad: the signed angle it was turned from the pose, towards flexion [rad].
        foot_shift_m: the foot body's horizontal displacement, world (x, y) [m].
        lever_m: the knee's distance from the nearer end of the foot's path [m].
    """

    joint: str
    flexion_rad: float
    foot_shift_m: tuple[float, float]
    lever_m: float


@dataclass(frozen=True)
class FacingVote:
    """One kind of evidence on the sign of forward along the feet's long axis.

    Attributes:
        source: ``"names"``, ``"knees"`` or ``"toes"``.
        sign: +1 or -1 along the axis; 0 when this evidence says nothing.
        strong: whether it is reliable on its own (module docstring).
        evidence: what was seen, one clause.
    """

    source: str
    sign: int
    strong: bool
    evidence: str


def path_to_root(model: mujoco.MjModel, body: int) -> list[int]:
    """The bodies from just below the world down to ``body``, top first."""
    path = [body]
    while int(model.body_parentid[path[-1]]) != 0:
        path.append(int(model.body_parentid[path[-1]]))
    return path[::-1]


def _hinges_above(model: mujoco.MjModel, foot: int) -> list[int]:
    """The hinge joints from the root down to ``foot``, top first."""
    return [
        j
        for b in path_to_root(model, foot)
        for j in range(model.body_jntadr[b], model.body_jntadr[b] + model.body_jntnum[b])
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE
    ]


def _flexion(model: mujoco.MjModel, joint: int, angle: float) -> float:
    """Signed flexion towards the range's longer side (0 for an even or free range)."""
    if not model.jnt_limited[joint]:
        return 0.0
    low, high = (float(v) for v in model.jnt_range[joint])
    ahead, behind = high - angle, angle - low
    if ahead > ONE_SIDED * max(behind, 0.0) and ahead > 0.0:
        return min(FLEXION_RAD, 0.5 * ahead)
    if behind > ONE_SIDED * max(ahead, 0.0) and behind > 0.0:
        return -min(FLEXION_RAD, 0.5 * behind)
    return 0.0


def knee_flexion(model: mujoco.MjModel, qpos: NDArray[np.float64], foot: int) -> KneeFlexion | None:
    r"""The knee above ``foot`` flexed from the pose ``qpos`` (module docstring).

    The knee is the hinge whose anchor lies furthest from both ends of the foot's path (the
    top joint and the foot: :math:`\max \min(|a - a_{top}|, |a - p_{foot}|)`), where the leg
    folds; None when that joint's range is not one-sided or its flexion moves the foot less
    than :data:`FOLDS_M`.
    """
    hinges = _hinges_above(model, foot)
    if len(hinges) < 3:
        return None
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    top = data.xanchor[hinges[0]].copy()
    before = data.xpos[foot].copy()
    lever = [
        min(np.linalg.norm(data.xanchor[j] - top), np.linalg.norm(data.xanchor[j] - before))
        for j in hinges
    ]
    knee = hinges[int(np.argmax(lever))]
    address = int(model.jnt_qposadr[knee])
    flexion = _flexion(model, knee, float(qpos[address]))
    if flexion == 0.0:
        return None
    data.qpos[address] += flexion
    mujoco.mj_kinematics(model, data)
    shift = data.xpos[foot][:2] - before[:2]
    if float(np.linalg.norm(shift)) < FOLDS_M:
        return None
    return KneeFlexion(
        joint=model.joint(knee).name,
        flexion_rad=flexion,
        foot_shift_m=(float(shift[0]), float(shift[1])),
        lever_m=float(max(lever)),
    )


_LEFT = {"left", "l", "lleg", "lfoot"}
_RIGHT = {"right", "r", "rleg", "rfoot"}


def _tokens(name: str) -> set[str]:
    spaced = re.sub(r"([a-z0-9])([A-Z])|([A-Z])([A-Z][a-z])", r"\1\3 \2\4", name)
    return {t for t in re.split(r"[^A-Za-z0-9]+|(?<=[A-Za-z])(?=[0-9])", spaced.lower()) if t}


def side_from_names(names: Sequence[str]) -> str | None:
    """``"left"``, ``"right"`` or None from body or joint names (their tokens, module docstring)."""
    left = right = 0
    for name in names:
        tokens = _tokens(name)
        left += bool(tokens & _LEFT) and not tokens & _RIGHT
        right += bool(tokens & _RIGHT) and not tokens & _LEFT
    if left and not right:
        return "left"
    if right and not left:
        return "right"
    return None


def _path_names(model: mujoco.MjModel, foot: int, shared: set[int]) -> list[str]:
    """Names of the foot's own bodies and joints (those no other foot hangs from)."""
    bodies = [b for b in path_to_root(model, foot) if b not in shared]
    joints = [
        model.joint(j).name
        for b in bodies
        for j in range(model.body_jntadr[b], model.body_jntadr[b] + model.body_jntnum[b])
    ]
    return [model.body(b).name for b in bodies] + joints


def facing_votes(
    model: mujoco.MjModel, data: mujoco.MjData, feet: Sequence[int], axis: int, toes: FacingVote
) -> tuple[FacingVote, ...]:
    """The names', the knees' and the toes' votes on forward along world ``axis`` (0: x, 1: y).

    Args:
        model: the model, posed in ``data`` (kinematics done).
        data: its data at the initial pose.
        feet: the two foot bodies.
        axis: the feet's long horizontal axis.
        toes: the toes' vote, measured by the caller from the feet's collision geoms.
    """
    label = "xy"[axis]
    shared = set(path_to_root(model, feet[0])) & set(path_to_root(model, feet[1]))
    sides = [side_from_names(_path_names(model, f, shared)) for f in feet]
    if sorted(s or "" for s in sides) == ["left", "right"]:
        left, right = (feet[0], feet[1]) if sides[0] == "left" else (feet[1], feet[0])
        leftward = data.xpos[left][:2] - data.xpos[right][:2]
        forward = np.array([leftward[1], -leftward[0]])  # ℓ × z
        sign = 1 if forward[axis] >= 0.0 else -1
        names = FacingVote(
            "names",
            sign,
            True,
            f"{model.body(left).name} is named left and stands on the left when facing "
            f"{'+' if sign > 0 else '-'}{label}",
        )
    else:
        names = FacingVote("names", 0, True, "the feet's names do not say left and right")
    shifts = [knee_flexion(model, data.qpos.copy(), f) for f in feet]
    bent = [k for k in shifts if k is not None]
    backwards = sum(k.foot_shift_m[axis] for k in bent)
    if bent and abs(backwards) > 0.0:
        sign = -1 if backwards > 0.0 else 1
        joints = " and ".join(k.joint for k in bent)
        knees = FacingVote(
            "knees",
            sign,
            True,
            f"flexing {joints} carries the feet {abs(backwards) / len(bent):.3f} m towards "
            f"{'-' if sign > 0 else '+'}{label} (backwards)",
        )
    else:
        knees = FacingVote("knees", 0, True, "no knee bends one way only")
    return (names, knees, toes)


def decide(votes: Sequence[FacingVote]) -> tuple[int, bool]:
    """The sign of forward (the first vote cast, in the given order) and whether it is sure.

    Sure when a strong vote is cast, no strong vote disagrees, and a disagreeing weak vote is
    outweighed by two strong ones.
    """
    cast = [v for v in votes if v.sign != 0]
    if not cast:
        return 1, False
    sign = cast[0].sign
    strong = [v for v in cast if v.strong]
    weak_disagrees = any(v.sign != sign for v in cast if not v.strong)
    sure = (
        bool(strong)
        and all(v.sign == sign for v in strong)
        and (not weak_disagrees or len(strong) >= 2)
    )
    return sign, sure
