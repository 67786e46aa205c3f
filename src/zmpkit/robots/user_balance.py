"""The balance model of a user's robot, derived from its model standing at its initial pose.

- **mass**: the whole robot's mass (sole plates included) [kg];
- **CoM height**: the standing CoM above the soles [m];
- **support polygon**: the double-support extent of the two soles (their rectangles around
  the sole centres, :attr:`~zmpkit.robots.user_model.FootPrint` size), per plane [m];
- **lean**: the whole-body IK lean (:mod:`zmpkit.experiments.whole_body_lean`); its pivots
  measure the lean angle: the last pitch joint (sagittal) and the last roll joint (frontal) of
  each leg, i.e. the ankle's; the hip roll joints are the legs' first roll joints;
- **push bodies**: ``com`` on the root body, ``trunk`` on the torso body.

A leg without a pitch and a roll joint (a world axis along y and along x) has no ankle to
measure the lean by: the robot then has no balance model.
"""

from __future__ import annotations

import mujoco
import numpy as np

from zmpkit.robots.robot import BalanceModel
from zmpkit.robots.robot_file import SIDES, RobotFile
from zmpkit.robots.user_model import UserModel, root_body
from zmpkit.robots.user_walking import axis_joints
from zmpkit.sim.names import sole_site
from zmpkit.sim.servo import ServoLimits

__all__ = ["LEAN_CONTROL_PERIOD_S", "LEAN_ZMP_MARGIN", "lean_limits", "user_balance"]

LEAN_CONTROL_PERIOD_S = 0.01
"""Period at which a user's robot's lean controller is stepped [s]."""
LEAN_ZMP_MARGIN = 0.25
"""The lean's acceleration may shift the ZMP by this share of the half sole length [-]."""
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
    if not all(pitch[s] and roll[s] for s in SIDES):
        return None
    sole_z = float(np.mean([data.site(sole_site(s)).xpos[2] for s in SIDES]))
    root = root_body(model)
    return BalanceModel(
        mass_kg=float(model.body_subtreemass[0]),
        com_height_m=float(data.subtree_com[0][2]) - sole_z,
        support_polygon_m=_support(data, built),
        lean_joints={
            "sagittal": (pitch["right"][-1], pitch["left"][-1]),
            "frontal": (roll["right"][-1], roll["left"][-1]),
        },
        hip_roll_joints=(roll["right"][0], roll["left"][0]),
        push_bodies={"com": root, "trunk": file.torso or root},
        control_period_s=LEAN_CONTROL_PERIOD_S,
        lean="whole_body",
        lean_limits=lean_limits(
            float(data.subtree_com[0][2]) - sole_z,
            min(foot.length_m for foot in built.feet.values()),
        ),
    )
