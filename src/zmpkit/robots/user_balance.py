"""The balance model of a user's robot, derived from its model standing at its initial pose.

- **mass**: the whole robot's mass (sole plates included) [kg];
- **CoM height**: the standing CoM above the soles [m];
- **support polygon**: the double-support extent of the two soles (their rectangles around
  the sole centres, :attr:`~zmpkit.robots.user_feet.FootPrint` size), per plane [m];
- **lean**: the whole-body IK lean (:mod:`zmpkit.experiments.whole_body_lean`); its pivots
  measure the lean angle: each leg's ankle pitch joint (sagittal) and ankle roll joint
  (frontal): its last joint about that axis (world y, x), when that joint's anchor lies
  within :data:`ANKLE_HEIGHT_SHARE` of the hip's height above the sole; the hip roll joints
  are the legs' first roll joints;
- **push bodies**: ``com`` on the root body, ``trunk`` on the torso body.

A robot leans only in the planes both its legs have an ankle joint for (a leg without an
ankle roll joint cannot shift the ZMP sideways about the ankle: its hip roll would be asked
for a lean it cannot make); the others are in
:attr:`~zmpkit.robots.robot.BalanceModel.missing_planes` with the reason. A robot with an
ankle joint in neither plane has no balance model.
"""

from __future__ import annotations

import mujoco
import numpy as np

from zmpkit.robots.robot import BalanceModel
from zmpkit.robots.robot_file import SIDES, RobotFile
from zmpkit.robots.user_model import UserModel
from zmpkit.robots.user_model_file import root_body
from zmpkit.robots.user_walking import axis_joints
from zmpkit.sim.names import sole_site
from zmpkit.sim.servo import ServoLimits

__all__ = [
    "ANKLE_HEIGHT_SHARE",
    "LEAN_CONTROL_PERIOD_S",
    "LEAN_ZMP_MARGIN",
    "lean_limits",
    "user_balance",
]

LEAN_CONTROL_PERIOD_S = 0.01
"""Period at which a user's robot's lean controller is stepped [s]."""
LEAN_ZMP_MARGIN = 0.25
"""The lean's acceleration may shift the ZMP by this share of the half sole length [-]."""
ANKLE_HEIGHT_SHARE = 0.35
"""A leg's last pitch (roll) joint is its ankle's when its anchor lies below this share of
the hip's height above the sole (a knee sits near half of it) [-]."""
LEAN_TIME_S = 0.5
"""The lean's velocity limit lets it cross its acceleration-limited range in about this [s]."""


def _support(data: mujoco.MjData, built: UserModel) -> dict[str, tuple[float, float]]:
    """Double-support extent of both soles along x and y, world frame [m]."""
    low, high = np.full(2, np.inf), np.full(2, -np.inf)
    for side in SIDES:
        foot = built.feet[side]
        centre = np.asarray(data.site(sole_site(side)).xpos[:2])
        half = np.array([foot.length_m, foot.width_m]) / 2.0
        low, high = np.minimum(low, centre - half), np.maximum(high, centre + half)
    return {
        "sagittal": (float(low[0]), float(high[0])),
        "frontal": (float(low[1]), float(high[1])),
    }


def lean_limits(com_height_m: float, sole_length_m: float) -> ServoLimits:
    r"""Lean-angle limits that keep the feet flat.

    A lean :math:`\ddot\theta` accelerates the CoM by :math:`l \ddot\theta`, which moves the
    ZMP by :math:`(l^2/g) \ddot\theta`; keeping that within :data:`LEAN_ZMP_MARGIN` of half
    the sole gives :math:`\ddot\theta_{max} = 0.5 \, m \, L_{sole} \, g / l^2` [rad/s²],
    and :math:`\dot\theta_{max} = \ddot\theta_{max}` × :data:`LEAN_TIME_S` [rad/s].

    Args:
        com_height_m: standing CoM height :math:`l` [m].
        sole_length_m: sole length :math:`L_{sole}` [m].
    """
    acceleration = 0.5 * LEAN_ZMP_MARGIN * sole_length_m * 9.81 / com_height_m**2
    return ServoLimits(acceleration * LEAN_TIME_S, acceleration)


def user_balance(file: RobotFile, built: UserModel) -> BalanceModel | None:
    """The balance model of a user's robot (module docstring), or None without ankles."""
    model = mujoco.MjModel.from_xml_string(built.mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    pitch = {s: axis_joints(model, data, file.legs[s], 1) for s in SIDES}
    roll = {s: axis_joints(model, data, file.legs[s], 0) for s in SIDES}
    lean_joints, missing = {}, {}
    for plane, joints, kind in (("sagittal", pitch, "pitch"), ("frontal", roll, "roll")):
        ankles = [_ankle(model, data, file, s, joints[s]) for s in SIDES]
        if ankles[0] is not None and ankles[1] is not None:
            lean_joints[plane] = (ankles[0], ankles[1])
        else:
            lacking = [s for s, a in zip(SIDES, ankles, strict=True) if a is None]
            missing[plane] = (
                f"neither leg has an ankle {kind} joint"
                if len(lacking) == 2
                else f"the {lacking[0]} leg has no ankle {kind} joint"
            )
    if not lean_joints:
        return None
    sole_z = float(np.mean([data.site(sole_site(s)).xpos[2] for s in SIDES]))
    root = root_body(model)
    return BalanceModel(
        mass_kg=float(model.body_subtreemass[0]),
        com_height_m=float(data.subtree_com[0][2]) - sole_z,
        support_polygon_m=_support(data, built),
        lean_joints=lean_joints,
        hip_roll_joints=(roll["right"][0], roll["left"][0])
        if roll["right"] and roll["left"]
        else ("", ""),
        push_bodies={"com": root, "trunk": file.torso or root},
        control_period_s=LEAN_CONTROL_PERIOD_S,
        lean="whole_body",
        lean_limits=lean_limits(
            float(data.subtree_com[0][2]) - sole_z,
            min(foot.length_m for foot in built.feet.values()),
        ),
        missing_planes=missing,
    )


def _ankle(
    model: mujoco.MjModel, data: mujoco.MjData, file: RobotFile, side: str, joints: list[str]
) -> str | None:
    """The last of ``joints`` if it sits at the ankle (module docstring), else None."""
    if not joints:
        return None
    sole_z = float(data.site(sole_site(side)).xpos[2])
    hip_z = float(data.xanchor[model.joint(file.legs[side][0]).id][2]) - sole_z
    ankle_z = float(data.xanchor[model.joint(joints[-1]).id][2]) - sole_z
    return joints[-1] if ankle_z <= ANKLE_HEIGHT_SHARE * hip_z else None
