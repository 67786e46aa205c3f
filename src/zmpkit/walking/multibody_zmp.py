r"""ZMP of the whole floating-base robot by inverse dynamics (Algorithm 1's "Newton–Euler").

For a configuration ``q`` with velocity ``v`` and acceleration ``a``, MuJoCo's ``mj_inverse``
returns the generalised force :math:`\tau = M(q) a + c(q, v) - \tau_{passive}` that produces
them. With contacts and constraints disabled nothing but that force acts, and on the six
free-joint coordinates nothing is actuated: their entries are exactly the external wrench the
ground must apply, the force :math:`F` [N] in the world frame and the moment
:math:`\tau_o` [N·m] about the base origin ``o`` in the base frame (MuJoCo's free joint). Its
centre of pressure on the floor z = 0 is the multibody ZMP:

.. math::

    p_x = o_x - \frac{\tau_y + o_z F_x}{F_z}, \qquad
    p_y = o_y + \frac{\tau_x - o_z F_y}{F_z}, \qquad \tau = R_{base}\,\tau_o.

Why MuJoCo: it is the same model and the same dynamics the simulator integrates (no second
robot description to keep in step), ``mj_inverse`` is compiled C (a few µs per sample), and it
adds no dependency (Pinocchio would add one and a URDF export).

Over a trajectory sampled every ``dt`` the velocities and accelerations are central finite
differences on the configuration manifold (``mj_differentiatePos``, which handles the base
quaternion): :math:`v_k = \Delta(q_{k-1}, q_{k+1}) / 2dt`,
:math:`a_k = (\Delta(q_k, q_{k+1}) - \Delta(q_{k-1}, q_k)) / dt^2`, second order in ``dt``;
the first and last samples are taken at rest (a walking pattern starts and ends standing).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError, ParameterError
from zmpkit.walking.ik import JointTrajectory

__all__ = [
    "MIN_VERTICAL_FORCE_N",
    "InverseDynamicsZmp",
    "MultibodyZmp",
    "expected_zmp_offset",
    "finite_differences",
    "trajectory_qpos",
]

MIN_VERTICAL_FORCE_N = 1e-6
"""Below this required vertical force the robot would fly and the ZMP is undefined [N]."""
_DISABLED = (
    mujoco.mjtDisableBit.mjDSBL_CONTACT
    | mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    | mujoco.mjtDisableBit.mjDSBL_SENSOR
)


@dataclass(frozen=True)
class MultibodyZmp:
    """The ground wrench a trajectory requires, and its ZMP.

    Attributes:
        zmp_in_world: [m], shape (N, 2); NaN where the required F_z is not positive.
        force_in_world: ground force on the robot [N], shape (N, 3).
        moment_about_base_in_world: its moment about the base origin [N·m], shape (N, 3).
    """

    zmp_in_world: NDArray[np.float64]
    force_in_world: NDArray[np.float64]
    moment_about_base_in_world: NDArray[np.float64]


def finite_differences(
    model: mujoco.MjModel, qpos: NDArray[np.float64], dt_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Central-difference velocity [m/s, rad/s] and acceleration, shape (N, nv) each.

    Args:
        model: the model whose configurations ``qpos`` holds.
        qpos: configurations, shape (N, nq), N >= 3.
        dt_s: sampling period [s].
    """
    if qpos.ndim != 2 or qpos.shape[1] != model.nq or qpos.shape[0] < 3:
        raise ParameterError(f"qpos must have shape (N >= 3, {model.nq}); got {qpos.shape}")
    if not dt_s > 0.0:
        raise ParameterError(f"dt_s must be > 0 s; got {dt_s}")
    n = qpos.shape[0]
    delta = _position_differences(model, qpos)
    qvel, qacc = np.zeros((n, model.nv)), np.zeros((n, model.nv))
    qvel[1:-1] = (delta[1:] + delta[:-1]) / (2.0 * dt_s)
    qacc[1:-1] = (delta[1:] - delta[:-1]) / dt_s**2
    return qvel, qacc


def _position_differences(model: mujoco.MjModel, qpos: NDArray[np.float64]) -> NDArray[np.float64]:
    """``mj_differentiatePos`` of consecutive configurations, shape (N − 1, nv).

    A free base followed by hinge/slide joints (every walking robot here) is done in one
    vectorised pass: linear part in the world frame, angular part the rotation vector of
    q_k⁻¹ q_{k+1} in the base frame, as MuJoCo does; other models use MuJoCo per sample.
    """
    if _free_base_and_scalar_joints(model):
        delta = np.empty((qpos.shape[0] - 1, model.nv))
        delta[:, :3] = np.diff(qpos[:, :3], axis=0)
        delta[:, 3:6] = _quaternion_log_difference(qpos[:-1, 3:7], qpos[1:, 3:7])
        delta[:, 6:] = np.diff(qpos[:, 7:], axis=0)
        return delta
    delta = np.empty((qpos.shape[0] - 1, model.nv))
    for k in range(qpos.shape[0] - 1):
        mujoco.mj_differentiatePos(model, delta[k], 1.0, qpos[k], qpos[k + 1])
    return delta


def _free_base_and_scalar_joints(model: mujoco.MjModel) -> bool:
    """Whether joint 0 is free and every other joint a hinge or slide."""
    types = [int(t) for t in model.jnt_type]
    scalar = {int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)}
    return bool(types) and types[0] == int(mujoco.mjtJoint.mjJNT_FREE) and set(types[1:]) <= scalar


def _quaternion_log_difference(
    q1: NDArray[np.float64], q2: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Rotation vectors [rad] of q1⁻¹ q2 (rows w, x, y, z), shortest way, in q1's frame."""
    w1, v1 = q1[:, :1], -q1[:, 1:]  # conjugate of q1
    w2, v2 = q2[:, :1], q2[:, 1:]
    w = w1 * w2 - np.sum(v1 * v2, axis=1, keepdims=True)
    v = w1 * v2 + w2 * v1 + np.cross(v1, v2)
    flip = np.where(w < 0.0, -1.0, 1.0)
    w, v = w * flip, v * flip
    sin_half = np.linalg.norm(v, axis=1, keepdims=True)
    angle = 2.0 * np.arctan2(sin_half, w)
    scale = np.divide(angle, sin_half, out=np.full_like(angle, 2.0), where=sin_half > 1e-12)
    return v * scale


def trajectory_qpos(model: mujoco.MjModel, trajectory: JointTrajectory) -> NDArray[np.float64]:
    """Whole configurations (N, nq) of an IK trajectory: its base pose and joint angles."""
    qpos = np.tile(model.qpos0, (trajectory.time_s.size, 1))
    qpos[:, :7] = trajectory.base_qpos
    for i, name in enumerate(trajectory.joint_names):
        joint_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if joint_id < 0:
            raise ModelError(f"the model has no joint {name!r} of the trajectory")
        qpos[:, int(model.jnt_qposadr[joint_id])] = trajectory.q_rad[:, i]
    return qpos


def _base_rotation(quat_wxyz: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrices (N, 3, 3) of unit quaternions (N, 4)."""
    q = quat_wxyz / np.linalg.norm(quat_wxyz, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def _centre_of_pressure(
    base_in_world: NDArray[np.float64],
    force: NDArray[np.float64],
    moment: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Point on z = 0 about which ``moment`` (about ``base``) has no x, y part [m], (N, 2)."""
    fz = force[:, 2]
    ok = fz > MIN_VERTICAL_FORCE_N
    fz = np.where(ok, fz, np.nan)
    o = base_in_world
    zmp_x = o[:, 0] - (moment[:, 1] + o[:, 2] * force[:, 0]) / fz
    zmp_y = o[:, 1] + (moment[:, 0] - o[:, 2] * force[:, 1]) / fz
    return np.column_stack([zmp_x, zmp_y])


class InverseDynamicsZmp:
    """Multibody ZMP of a floating-base MuJoCo model (module docstring).

    Args:
        model: the robot, a free joint first (copied; contacts, constraints and sensors are
            disabled in the copy).
    """

    def __init__(self, model: mujoco.MjModel) -> None:
        if model.njnt == 0 or model.jnt_type[0] != mujoco.mjtJoint.mjJNT_FREE:
            raise ModelError("the multibody ZMP needs a model whose first joint is free")
        self.model = copy.deepcopy(model)
        self.model.opt.disableflags |= int(_DISABLED)
        self.data = mujoco.MjData(self.model)

    def wrench(
        self, qpos: NDArray[np.float64], qvel: NDArray[np.float64], qacc: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Free-joint rows of ``mj_inverse`` per sample, shape (N, 6): F (world), tau_o (base)."""
        m, d = self.model, self.data
        # Local names and row iteration: this loop is the per-sample cost beyond mj_inverse.
        d_qpos, d_qvel, d_qacc, frc = d.qpos, d.qvel, d.qacc, d.qfrc_inverse
        inverse, rows = mujoco.mj_inverse, []
        for q, v, a in zip(qpos, qvel, qacc, strict=True):
            d_qpos[:] = q
            d_qvel[:] = v
            d_qacc[:] = a
            inverse(m, d)
            rows.append(frc[:6].copy())
        return np.array(rows).reshape(-1, 6)

    def from_states(
        self, qpos: NDArray[np.float64], qvel: NDArray[np.float64], qacc: NDArray[np.float64]
    ) -> MultibodyZmp:
        """The multibody ZMP of explicit states, each of shape (N, nq or nv)."""
        wrench = self.wrench(qpos, qvel, qacc)
        moment = np.einsum("nij,nj->ni", _base_rotation(qpos[:, 3:7]), wrench[:, 3:])
        zmp = _centre_of_pressure(qpos[:, :3], wrench[:, :3], moment)
        return MultibodyZmp(zmp, wrench[:, :3], moment)

    def from_qpos(self, qpos: NDArray[np.float64], dt_s: float) -> MultibodyZmp:
        """The multibody ZMP of configurations (N, nq) sampled every ``dt_s`` [s]."""
        qvel, qacc = finite_differences(self.model, qpos, dt_s)
        return self.from_states(qpos, qvel, qacc)

    def from_trajectory(self, trajectory: JointTrajectory) -> MultibodyZmp:
        """The multibody ZMP of an IK trajectory (its base pose and joint angles)."""
        dt = float(trajectory.time_s[1] - trajectory.time_s[0])
        return self.from_qpos(trajectory_qpos(self.model, trajectory), dt)


def expected_zmp_offset(
    model: mujoco.MjModel, trajectory: JointTrajectory, cart_table_zmp_in_world: NDArray[np.float64]
) -> NDArray[np.float64]:
    r"""What the multibody robot's ZMP adds to the cart table's on a planned walk [m], (N, 2).

    :math:`\Delta_k = p^{mb}_k - p^{ct}_k`: the multibody ZMP of the IK's motion on the design
    model (:class:`InverseDynamicsZmp`) minus the cart-table ZMP of the planned CoM,
    :math:`c - (z_c/g)\ddot c`; 0 where the multibody ZMP is undefined. On the default
    walking robot at 0.2 m/s it swings ±4 cm along x every step: the legs' own inertia,
    which the cart table leaves out and an observer of the measured ZMP would otherwise take
    for a disturbance.

    Args:
        model: the design model (a free joint first), the IK's.
        trajectory: the IK's solution of the plan.
        cart_table_zmp_in_world: the plan's cart-table ZMP per frame [m], shape (N, 2).
    """
    multibody = InverseDynamicsZmp(model).from_trajectory(trajectory).zmp_in_world
    offset = multibody - np.asarray(cart_table_zmp_in_world, dtype=np.float64)[:, :2]
    return np.nan_to_num(offset)
