r"""Joint-target offsets that pre-load soft position servos with the walk's joint torques.

A position servo with proportional gain :math:`k` [N·m/rad] (joint side), no integral term
and a velocity damping :math:`b` [N·m·s/rad] (a PWM drive's back-EMF: its stall torque over
its no-load speed) gives the joint torque :math:`k (q_{cmd} - q) - b \dot q`: it sags under
load and lags a moving target. Commanding the IK's angle :math:`q` then leaves the stance
leg bent by the body's weight (for a kid-size servo of 19 N·m/rad and 2 N·m, 0.1 rad), the
torso pitched and the feet landing off the plan. If the user knows the gain they set on
their servos and the damping of their drive, the walk can invert that servo model and
command

.. math:: q_{cmd} = q + (\tau_{ff} + b \dot q) / k

instead, with :math:`\tau_{ff}` the joint torques the planned motion needs and
:math:`\dot q` the planned joint speed (a feed-forward; feedback walks add it to their own
targets).

The torques come from the rigid design model (the IK's) moved along the IK's trajectory:
inverse dynamics (``mujoco.mj_inverse``, with the model's constraints and passive forces
switched off: no floor contact, joint limit, friction loss, joint damping or spring enters) at the
configuration, velocity and acceleration of each frame (central differences of the
trajectory) give the generalised forces :math:`f` that the rigid bodies' motion needs,
floating base included. The feet in contact carry the
base's six of them: with the contact Jacobians :math:`J_i` (6 × nv, at the sole centres) and
the wrenches :math:`w_i`, :math:`\sum_i J_{i,b}^T w_i = f_b`, solved for the wrenches of
least weighted norm :math:`\sum_i |w_i|^2 / a_i`, where :math:`a_i` is the share of the
weight the plan puts on foot :math:`i` (in double support, where the planned ZMP lies
between the sole centres; 1 in single support). The joints' torques are then
:math:`\tau = f_j - \sum_i J_{i,j}^T w_i`.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.walking.ik import IkSettings, JointTrajectory
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["MIN_FOOT_SHARE", "planned_joint_torques", "servo_compliance_offsets"]

MIN_FOOT_SHARE = 1e-3
"""Smallest weight share a foot in contact gets in the least-norm split [-] (keeps it
well posed when the planned ZMP sits on one foot in double support)."""
_FREE_DOFS = 6


def _qpos(model: mujoco.MjModel, trajectory: JointTrajectory) -> NDArray[np.float64]:
    """The design model's configuration at every frame, shape (N, nq)."""
    qpos = np.tile(model.qpos0, (trajectory.time_s.size, 1))
    qpos[:, :7] = trajectory.base_qpos
    adr = [int(model.joint(j).qposadr[0]) for j in trajectory.joint_names]
    qpos[:, adr] = trajectory.q_rad
    return qpos


def _velocities(model: mujoco.MjModel, qpos: NDArray[np.float64], dt: float) -> NDArray[np.float64]:
    """Central-difference velocities [rad/s, m/s], zero at both ends, shape (N, nv)."""
    qvel = np.zeros((qpos.shape[0], model.nv))
    for k in range(1, qpos.shape[0] - 1):
        mujoco.mj_differentiatePos(model, qvel[k], 2.0 * dt, qpos[k - 1], qpos[k + 1])
    return qvel


def _foot_shares(sole_xy: list[NDArray[np.float64]], zmp_xy: NDArray[np.float64]) -> list[float]:
    """Weight shares of the feet in contact (module docstring) [-]."""
    if len(sole_xy) == 1:
        return [1.0]
    first, second = sole_xy
    line = first - second
    length2 = float(line @ line)
    share = 0.5 if length2 == 0.0 else float((zmp_xy - second) @ line) / length2
    share = min(max(share, MIN_FOOT_SHARE), 1.0 - MIN_FOOT_SHARE)
    return [share, 1.0 - share]


def planned_joint_torques(
    pattern: WalkingPattern,
    trajectory: JointTrajectory,
    model: mujoco.MjModel,
    settings: IkSettings,
) -> NDArray[np.float64]:
    """The joint torques the planned walk needs [N·m], shape (N, J) (module docstring).

    Args:
        pattern: the planned walk (its feet's contact phases and ZMP reference).
        trajectory: its IK on ``model`` (joints in ``trajectory.joint_names`` order).
        model: the rigid design model with a free base (the IK's); not modified.
        settings: the IK's settings (its sole sites).
    """
    model = copy.copy(model)
    for flag in ("mjDSBL_CONSTRAINT", "mjDSBL_DAMPER", "mjDSBL_SPRING"):
        model.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, flag))
    dt = float(trajectory.time_s[1] - trajectory.time_s[0])
    qpos = _qpos(model, trajectory)
    qvel = _velocities(model, qpos, dt)
    qacc = np.gradient(qvel, dt, axis=0)
    dofs = [int(model.joint(j).dofadr[0]) for j in trajectory.joint_names]
    contact = {"left": pattern.feet.left.in_contact, "right": pattern.feet.right.in_contact}
    sites = {side: model.site(name).id for side, name in settings.sole_sites.items()}
    data = mujoco.MjData(model)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    torques = np.zeros((qpos.shape[0], len(dofs)))
    for k in range(qpos.shape[0]):
        data.qpos[:], data.qvel[:], data.qacc[:] = qpos[k], qvel[k], qacc[k]
        mujoco.mj_inverse(model, data)
        force = data.qfrc_inverse.copy()
        feet = [side for side in ("left", "right") if contact[side][min(k, contact[side].size - 1)]]
        if feet:
            jacobians = []
            for side in feet:
                mujoco.mj_jacSite(model, data, jacp, jacr, sites[side])
                jacobians.append(np.vstack([jacp, jacr]))
            soles = [np.asarray(data.site_xpos[sites[side]][:2]) for side in feet]
            shares = _foot_shares(soles, pattern.zmp_reference_in_world[k])
            base = np.hstack([j[:, :_FREE_DOFS].T for j in jacobians])  # (6, 6 n)
            weight = np.repeat(shares, 6)
            wrench = weight * (base.T @ np.linalg.solve((base * weight) @ base.T, force[:6]))
            for i, jacobian in enumerate(jacobians):
                force -= jacobian.T @ wrench[6 * i : 6 * i + 6]
        torques[k] = force[dofs]
    return torques


def servo_compliance_offsets(
    pattern: WalkingPattern,
    trajectory: JointTrajectory,
    model: mujoco.MjModel,
    settings: IkSettings,
    stiffness_nm_per_rad: float,
    damping_nm_s_per_rad: float = 0.0,
) -> NDArray[np.float64]:
    """The offsets ``(tau_ff + b q_dot) / k`` to add to the IK's targets [rad], shape (N, J).

    Args:
        pattern: the planned walk.
        trajectory: its IK on ``model``.
        model: the rigid design model (the IK's).
        settings: the IK's settings.
        stiffness_nm_per_rad: the servos' proportional gain at the joint, ``k`` [N·m/rad].
        damping_nm_s_per_rad: the servos' velocity damping at the joint, ``b`` [N·m·s/rad].
    """
    k = _validate.positive("stiffness_nm_per_rad", stiffness_nm_per_rad, "N·m/rad")
    b = _validate.non_negative("damping_nm_s_per_rad", damping_nm_s_per_rad, "N·m·s/rad")
    torques = planned_joint_torques(pattern, trajectory, model, settings)
    speed = np.gradient(trajectory.q_rad, trajectory.time_s, axis=0)
    return (torques + b * speed) / k
