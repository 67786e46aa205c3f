r"""The ankle-strategy lean: which joints lean the robot, and its design lean length.

In double support with both feet flat, the classic ankle strategy (paper A Fig. 9) leans the
robot about its ankles. Statically the ZMP sits under the CoM, so a lean by :math:`\theta`
moves it by

.. math:: x_{exp}(\theta) = l_{lean} \sin\theta, \qquad
    \theta_{ref} = \arcsin(x_{ref} / l_{lean}),

where :math:`l_{lean} = \partial x_{CoM} / \partial\theta` at the upright pose: the first moment
of the *moving* masses about the ankle axis divided by all the mass the F-T sensors weigh. The
feet (everything from the ankle's pivot joint down) stay. On paper A's robot the ankle axis is
0.123 m above the sole, so :math:`l_{lean}` (≈ 0.777 m sagittal) is well short of the 0.893 m
CoM height of its pendulum, which is measured from the ground.

Planes (lean angle :math:`\theta > 0` moves the ZMP toward +x, resp. +y):

- **sagittal** (ZMP x, forward): both ankle pitch joints (the robot's
  :attr:`~zmpkit.robots.robot.BalanceModel.lean_joints`); the legs stay straight and the whole
  robot rotates about the ankle axes.
- **frontal** (ZMP y, left): both ankle roll joints and the opposite hip roll joints
  (:attr:`~zmpkit.robots.robot.BalanceModel.hip_roll_joints`): the legs tilt, the feet stay
  flat, the pelvis shifts sideways. Legs that converge from the hips to the ankles (paper A's
  robot: y = ±0.146 m to ±0.1285 m) make the two legs, the pelvis and the ground a four-bar
  linkage, not a parallelogram: equal and opposite angles would force the stiff servos against
  each other. The legs' roll angles and
  the pelvis roll are therefore solved from the closed chain (:meth:`LeanModel.joint_targets`);
  :math:`\theta` is the legs' mean tilt.

:math:`l_{lean}` and the linkage are *design knowledge*: computed once from the rigid design
model (the robot's MJCF with every effect off: its CAD geometry and masses, with the shipped
parameters), exactly what a user of the real robot has, never from a simulated robot's truth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import Protocol

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from zmpkit.errors import ParameterError
from zmpkit.experiments.whole_body_lean import whole_body_lean
from zmpkit.robots.robot import Robot
from zmpkit.signals.step_trial import PLANES
from zmpkit.sim.world import Simulation

__all__ = [
    "Lean",
    "LeanModel",
    "design_lean_model",
    "design_support_interval",
    "lean_angle",
    "lean_angle_joints",
]

_AXIS_INDEX = {"sagittal": 1, "frontal": 0}
_LEVER_STEP_RAD = 1e-4
_CLOSURE_BRACKET_RAD = 0.2
_BOX = 6  # mujoco.mjtGeom.mjGEOM_BOX


class Lean(Protocol):
    """A robot's static lean in one plane: :class:`LeanModel` or a whole-body IK lean."""

    @property
    def plane(self) -> str:
        """``"sagittal"`` or ``"frontal"``."""
        ...

    @property
    def lean_length_m(self) -> float:
        """The lean's pendulum length l_lean [m]."""
        ...

    def joint_targets(self, angle_rad: float) -> dict[str, float]:
        """Joint angles [rad] that lean the design robot by ``angle_rad`` [rad]."""
        ...

    def angle_joints(self) -> dict[str, float]:
        """The pivot joints and the signs that measure the lean angle [-]."""
        ...


def _rotate(vec: NDArray[np.float64], angle: float) -> NDArray[np.float64]:
    """Rotate in-plane points (horizontal, z), shape (..., 2), so +angle tips +z toward +h."""
    c, s = math.cos(angle), math.sin(angle)
    h, z = vec[..., 0], vec[..., 1]
    return np.stack([h * c + z * s, -h * s + z * c], axis=-1)


@dataclass(frozen=True, eq=False)
class LeanModel:
    r"""The static lean of a design model in one plane.

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        lean_length_m: :math:`l_{lean} = \partial x_{CoM} / \partial \theta` at upright [m].
        axis_signs: per side, the sign of the pivot joint axis along the plane normal [-].
        ankles: frontal: ankle roll axes (y, z) of right and left, shape (2, 2) [m].
        hips: frontal: hip roll axes (y, z) of right and left, shape (2, 2) [m].
        pivots: the pivot joints of right and left in this plane.
        hip_rolls: the hip roll joints of right and left (they close the frontal chain).
    """

    plane: str
    lean_length_m: float
    axis_signs: tuple[float, float]
    ankles: NDArray[np.float64]
    hips: NDArray[np.float64]
    pivots: tuple[str, str]
    hip_rolls: tuple[str, str]

    def leg_tilts(self, angle_rad: float) -> tuple[float, float, float]:
        """Frontal closed chain: right and left leg tilt, pelvis tilt, for lean ``angle_rad`` [rad].

        Tilts are the in-plane rotations of :func:`_rotate` (+ tips toward +y); the legs'
        difference is solved so the hip-to-hip distance keeps its design length.
        """
        legs = self.hips - self.ankles
        width = float(np.linalg.norm(self.hips[1] - self.hips[0]))

        def hips_at(delta: float) -> NDArray[np.float64]:
            return np.stack(
                [
                    self.ankles[0] + _rotate(legs[0], angle_rad + delta),
                    self.ankles[1] + _rotate(legs[1], angle_rad - delta),
                ]
            )

        def gap(delta: float) -> float:
            h = hips_at(delta)
            return float(np.linalg.norm(h[1] - h[0])) - width

        delta = (
            0.0
            if gap(0.0) == 0.0
            else brentq(gap, -_CLOSURE_BRACKET_RAD, _CLOSURE_BRACKET_RAD, xtol=1e-15)
        )
        h, h0 = hips_at(delta), self.hips
        pelvis = math.atan2(h[1, 1] - h[0, 1], h[1, 0] - h[0, 0]) - math.atan2(
            h0[1, 1] - h0[0, 1], h0[1, 0] - h0[0, 0]
        )
        return angle_rad + delta, angle_rad - delta, -pelvis

    def joint_targets(self, angle_rad: float) -> dict[str, float]:
        """Joint angles [rad] that lean the design robot by ``angle_rad`` with the feet flat."""
        if self.plane == "sagittal":
            return {p: -sg * angle_rad for p, sg in zip(self.pivots, self.axis_signs, strict=True)}
        right, left, pelvis = self.leg_tilts(angle_rad)
        out: dict[str, float] = {}
        for k, tilt in enumerate((right, left)):
            sign = self.axis_signs[k]
            out[self.pivots[k]] = sign * tilt
            out[self.hip_rolls[k]] = -sign * (tilt - pelvis)
        return out

    def angle_joints(self) -> dict[str, float]:
        r"""The pivot joints and ``s_j`` with :math:`\theta = \operatorname{mean}_j(s_j q_j)` [-].

        Sagittal: exact. Frontal: the pivots are the legs' tilts, whose mean is :math:`\theta`.
        """
        flip = -1.0 if self.plane == "sagittal" else 1.0
        return {p: flip * sign for p, sign in zip(self.pivots, self.axis_signs, strict=True)}


def lean_angle(target_m: float, lean_length_m: float) -> float:
    r"""The LIPM lean angle :math:`\arcsin(x_{ref} / l_{lean})` for a ZMP target [rad].

    Raises:
        ParameterError: if :math:`|x_{ref}| \ge l_{lean}` (no angle reaches it).
    """
    if not abs(target_m) < lean_length_m:
        raise ParameterError(
            f"ZMP target {target_m} m is out of reach of a {lean_length_m:.4f} m lean; "
            f"expected |target| < {lean_length_m:.4f} m"
        )
    return math.asin(target_m / lean_length_m)


def _subtree(parent_ids: NDArray[np.int32], root: int) -> set[int]:
    """Bodies in the subtree of ``root`` (itself included); MuJoCo orders parents first."""
    inside = {root}
    for body in range(root + 1, len(parent_ids)):
        if int(parent_ids[body]) in inside:
            inside.add(body)
    return inside


@dataclass(frozen=True, eq=False)
class _DesignBodies:
    """Design-model bodies in one plane at the upright pose."""

    mass: NDArray[np.float64]  # [kg], weighed bodies only
    com: NDArray[np.float64]  # (k, 2) in-plane CoM (horizontal, z) [m]
    group: NDArray[np.int64]  # 0 foot, 1 right leg, 2 left leg, 3 carried by the pelvis


def _design_bodies(sim: Simulation, plane: str, model: LeanModel) -> _DesignBodies:
    m, d = sim.model, sim.data
    parents = m.body_parentid
    below = set().union(
        *(_subtree(parents, int(m.site_bodyid[m.site(f.site).id])) for f in sim.robot.feet)
    )
    group = np.full(m.nbody, 3)
    for k, (pivot, hip_roll) in enumerate(zip(model.pivots, model.hip_rolls, strict=True), 1):
        feet = _subtree(parents, int(m.jnt_bodyid[m.joint(pivot).id]))
        if plane == "frontal":
            hip = int(m.jnt_bodyid[m.joint(hip_roll).id])
            group[sorted(_subtree(parents, hip) - feet)] = k
        group[sorted(feet)] = 0
    keep = [b for b in range(1, m.nbody) if b not in below]
    column = 0 if plane == "sagittal" else 1
    com = np.column_stack([d.xipos[keep, column], d.xipos[keep, 2]])
    return _DesignBodies(np.asarray(m.body_mass[keep]), com, group[keep])


def _com(bodies: _DesignBodies, model: LeanModel, angle_rad: float) -> float:
    """Horizontal in-plane CoM of the weighed bodies at lean ``angle_rad`` [m]."""
    pos = bodies.com.copy()
    if model.plane == "sagittal":
        pivot_z = float(model.ankles[0, 1])
        moving = bodies.group != 0
        pivot = np.array([0.0, pivot_z])
        pos[moving] = pivot + _rotate(pos[moving] - pivot, angle_rad)
    else:
        right, left, pelvis = model.leg_tilts(angle_rad)
        for k, tilt in ((1, right), (2, left)):
            leg = bodies.group == k
            pos[leg] = model.ankles[k - 1] + _rotate(pos[leg] - model.ankles[k - 1], tilt)
        hip_r = model.ankles[0] + _rotate(model.hips[0] - model.ankles[0], right)
        top = bodies.group == 3
        pos[top] = hip_r + _rotate(pos[top] - model.hips[0], pelvis)
    return float(bodies.mass @ pos[:, 0] / bodies.mass.sum())


def _anchors(sim: Simulation, joints: tuple[str, str], plane: str) -> NDArray[np.float64]:
    m, d = sim.model, sim.data
    column = 0 if plane == "sagittal" else 1
    ids = [m.joint(joint).id for joint in joints]
    return np.array([[d.xanchor[i, column], d.xanchor[i, 2]] for i in ids])


def design_lean_model(robot: Robot, plane: str) -> Lean:
    """The lean of ``robot``'s design model in ``plane``: joints, linkage, lean length (cached).

    The design model is the rigid MJCF (effects ``"none"``, shipped parameters) standing upright.
    A robot whose balance model says ``lean="whole_body"`` gets the whole-body IK lean of
    :mod:`zmpkit.experiments.whole_body_lean`; the others the ankle strategy (:class:`LeanModel`).

    Args:
        robot: the robot.
        plane: ``"sagittal"`` or ``"frontal"``.

    Raises:
        ParameterError: on an unknown plane, naming the valid ones, or a robot without a
            balance model.
    """
    if plane not in PLANES:
        raise ParameterError(f"plane must be one of {', '.join(PLANES)}; got {plane!r}")
    return _design_lean_model(robot, plane)


@cache
def _design_lean_model(robot: Robot, plane: str) -> Lean:
    balance = robot.require_balance()
    if balance.lean == "whole_body":
        return whole_body_lean(robot, plane)
    pivots, hip_rolls = balance.require_plane(plane), balance.hip_roll_joints
    sim = robot.make_simulation("none")
    m, d = sim.model, sim.data
    axis = _AXIS_INDEX[plane]
    right, left = (float(np.sign(d.xaxis[m.joint(j).id, axis])) for j in pivots)
    signs = (right, left)
    ankles = _anchors(sim, pivots, plane)
    hips = _anchors(sim, hip_rolls, plane)
    model = LeanModel(plane, 0.0, signs, ankles, hips, pivots, hip_rolls)
    bodies = _design_bodies(sim, plane, model)
    step = _LEVER_STEP_RAD
    lever = (_com(bodies, model, step) - _com(bodies, model, -step)) / (2.0 * step)
    return LeanModel(plane, lever, signs, ankles, hips, pivots, hip_rolls)


def lean_angle_joints(robot: Robot, plane: str) -> dict[str, float]:
    """:meth:`LeanModel.angle_joints` of ``robot``'s design model in ``plane``."""
    return design_lean_model(robot, plane).angle_joints()


@cache
def design_support_interval(robot: Robot, plane: str) -> tuple[float, float]:
    """The support polygon of ``robot``'s design model standing, along ``plane``'s axis [m].

    The extent of the soles (the box geoms that touch the floor, below the foot F-T sensors)
    along x (sagittal) or y (frontal) in the world frame: a ZMP target outside it would lean
    the robot off its feet.

    Raises:
        ParameterError: on an unknown plane, naming the valid ones, or a robot without a
            balance model.
    """
    if plane not in PLANES:
        raise ParameterError(f"plane must be one of {', '.join(PLANES)}; got {plane!r}")
    robot.require_balance()
    sim = robot.make_simulation("none")
    m, d = sim.model, sim.data
    column = 0 if plane == "sagittal" else 1
    feet = set().union(
        *(_subtree(m.body_parentid, int(m.site_bodyid[m.site(f.site).id])) for f in sim.robot.feet)
    )
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    reach = []
    for g in range(m.ngeom):
        touches = m.geom_contype[g] or m.geom_conaffinity[g]
        if int(m.geom_bodyid[g]) in feet and touches and m.geom_type[g] == _BOX:
            corners = d.geom_xpos[g] + (signs * m.geom_size[g]) @ d.geom_xmat[g].reshape(3, 3).T
            reach.extend(corners[:, column])
    return float(min(reach)), float(max(reach))
