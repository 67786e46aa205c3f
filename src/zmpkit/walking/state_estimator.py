r"""Where a walking robot's CoM and ZMP are, from its encoders, IMU and F-T sensors.

A real robot has no motion capture: the controller places itself in the world through the
feet it stands on. Each tick, the robot's design model (the IK's rigid model) is put in the
measured configuration — joints from the encoders, the floating base's orientation from the
IMU — with the base at the origin (forward kinematics). That gives the CoM ``c_fk``, each sole
centre ``s_i``, each F-T sensor's origin ``o_i`` and rotation ``R_i``. The feet in contact are
where the footstep plan put them (``ŝ_i``), so the whole robot is shifted by the
contact-weighted anchor offset

.. math::

    Δ = \frac{\sum_i F_{z,i} (\hat s_i - s_i)}{\sum_i F_{z,i}}, \qquad
    \hat c = c_{fk} + Δ, \qquad \hat o_i = o_i + Δ

over the feet in contact (world ``F_z`` at least the contact threshold; weighting by force
makes the estimate continuous through double support). The ZMP follows from the wrenches
rotated into the world, ``R_i f_i`` and ``R_i τ_i``, about ``\hat o_i``
(:func:`zmpkit.sensors.zmp.zmp_in_world_now`). The CoM velocity is the finite difference of
``\hat c`` low-passed with time constant ``τ_v``:

.. math:: \hat v \leftarrow \hat v + \frac{T}{τ_v + T}\left(\frac{\hat c_k - \hat c_{k-1}}{T}
    - \hat v\right).

The IMU gives the base's roll and pitch, which gravity keeps honest; its yaw is the
integral of a gyroscope and drifts with its bias (0.05 rad/s turns it 0.5 rad in 10 s, and
the estimate with it: the built-in walker's feedback walks then fell on 3 of 4 seeds). Given the
planned headings ``ψ̂_i`` of the soles, the yaw comes from the feet in contact instead (leg
odometry, as the positions do): the posed robot is turned about the vertical through its base
by the contact-weighted heading error

.. math:: δψ = \frac{\sum_i F_{z,i}\,\operatorname{wrap}(\hat ψ_i - ψ_i)}{\sum_i F_{z,i}}

(``ψ_i`` from the posed sole's rotation) before the anchor; sole and sensor positions, the
CoM and the wrenches in the world turn with it. The feedback walks pass their feet's
headings (with the heading feedback's corrections); the gyro-bias walks then stand on all 4
seeds, and only the heading feedback, which reads the IMU's yaw on purpose, still sees the
bias (bounded by its 0.08 rad clamp).

The IMU is assumed on the floating base (the root body), as on the built-in robots.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ModelError
from zmpkit.sensors.zmp import zmp_in_world_now
from zmpkit.walking.measurement import WalkMeasurement

__all__ = ["KinematicStateEstimator"]

_TWO_PI = 2.0 * math.pi


def _site(model: mujoco.MjModel, name: str) -> int:
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
    if site < 0:
        raise ModelError(f"the design model has no site {name!r}")
    return int(site)


class KinematicStateEstimator:
    """CoM, its velocity and the ZMP in the world, from one :class:`WalkMeasurement` a tick.

    Args:
        model: the robot's rigid design model, floating base first (the IK's model).
        joint_names: the encoders' joints, in the measurement's order.
        sole_sites: foot -> site at its sole centre.
        sensor_sites: foot -> site of its F-T sensor (the wrench's frame and origin).
        imu_site: the IMU's site, on the root body.
        contact_threshold_n: world ``F_z`` from which a foot is in contact [N].
        period_s: the control period T [s].
        velocity_time_constant_s: τ_v of the velocity's low-pass [s].
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        joint_names: tuple[str, ...],
        sole_sites: dict[str, str],
        sensor_sites: dict[str, str],
        imu_site: str,
        contact_threshold_n: float,
        period_s: float,
        velocity_time_constant_s: float = 0.02,
    ) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self.feet = tuple(sole_sites)
        self.period_s = _validate.positive("period_s", period_s, "s")
        tau = _validate.non_negative("velocity_time_constant_s", velocity_time_constant_s, "s")
        self._blend = self.period_s / (tau + self.period_s)
        self.threshold_n = _validate.positive("contact_threshold_n", contact_threshold_n, "N")
        self._qadr = np.array([self._qpos_address(name) for name in joint_names])
        self._coupled = self._coupled_joints(set(self._qadr.tolist()))
        self._sole = [_site(model, sole_sites[f]) for f in self.feet]
        self._sensor = [_site(model, sensor_sites[f]) for f in self.feet]
        imu = _site(model, imu_site)
        if int(model.site_bodyid[imu]) != 1:
            raise ModelError(f"the IMU site {imu_site!r} must be on the root body")
        self._imu_in_base = np.empty(4)
        mujoco.mju_negQuat(self._imu_in_base, model.site_quat[imu])  # conjugate
        f = len(self.feet)
        self._force = np.zeros((f, 3))
        self._moment = np.zeros((f, 3))
        self._origin = np.zeros((f, 3))
        self._offset = np.zeros(3)
        self._anchor = np.zeros(3)
        self._com = np.zeros(3)
        self.com_in_world = np.zeros(3)
        """Estimated CoM [m], shape (3,)."""
        self.com_velocity_in_world = np.zeros(3)
        """Estimated CoM velocity [m/s], shape (3,)."""
        self.zmp_in_world = np.full(2, np.nan)
        """Estimated ZMP on the floor [m], shape (2,); NaN without contact."""
        self.force_z_n = np.zeros(f)
        """Each foot's vertical force in the world [N], shape (F,)."""
        self._started = False
        self.yaw_correction_rad = 0.0
        """The turn last applied to the IMU's yaw from the feet [rad]."""

    def _turn(self, yaw: float) -> None:
        """Turn the whole posed robot by ``yaw`` [rad] about the vertical through its base."""
        c, s = math.cos(yaw), math.sin(yaw)
        data = self.data
        rows = (*self._sole, *self._sensor)
        for vectors, index in (
            *((data.site_xpos, r) for r in rows),
            (data.subtree_com, 1),
            *((self._force, i) for i in range(len(self.feet))),
            *((self._moment, i) for i in range(len(self.feet))),
        ):
            x, y = float(vectors[index, 0]), float(vectors[index, 1])
            vectors[index, 0] = c * x - s * y
            vectors[index, 1] = s * x + c * y
        self.yaw_correction_rad = yaw

    def _qpos_address(self, name: str) -> int:
        joint = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if joint < 0:
            raise ModelError(f"the design model has no joint {name!r}")
        return int(self.model.jnt_qposadr[joint])

    def _coupled_joints(self, measured: set[int]) -> list[tuple[int, int, float, float]]:
        """Joints without an encoder that a joint equality ties to one that has one.

        Each as (qpos address, leader's qpos address, c0, c1): ``q = c0 + c1 q_leader``
        (e.g. a hip joint driven by the other leg's motor).
        """
        model, coupled = self.model, []
        for eq in range(model.neq):
            if model.eq_type[eq] != mujoco.mjtEq.mjEQ_JOINT or model.eq_obj2id[eq] < 0:
                continue
            follower = int(model.jnt_qposadr[model.eq_obj1id[eq]])
            leader = int(model.jnt_qposadr[model.eq_obj2id[eq]])
            if follower not in measured and leader in measured:
                c0, c1 = (float(v) for v in model.eq_data[eq, :2])
                coupled.append((follower, leader, c0, c1))
        return coupled

    def update(
        self,
        measurement: WalkMeasurement,
        planned_soles: NDArray[np.float64],
        planned_yaw: NDArray[np.float64] | None = None,
    ) -> None:
        """Estimate from one tick's measurement.

        Args:
            measurement: this tick's encoders, IMU and F-T wrenches.
            planned_soles: where the plan puts each sole centre now [m], shape (F, 3), in
                the order of ``sole_sites``.
            planned_yaw: each sole's planned heading now [rad], shape (F,); given, the
                base's yaw comes from the feet in contact instead of the IMU (module doc).
        """
        data, model = self.data, self.model
        data.qpos[:3] = 0.0
        mujoco.mju_mulQuat(data.qpos[3:7], measurement.imu_quaternion, self._imu_in_base)
        data.qpos[self._qadr] = measurement.q_meas_rad
        for follower, leader, c0, c1 in self._coupled:
            data.qpos[follower] = c0 + c1 * data.qpos[leader]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        total = 0.0
        force, moment = self._force, self._moment
        turn = 0.0
        for i, (sole, sensor) in enumerate(zip(self._sole, self._sensor, strict=True)):
            rotation = data.site_xmat[sensor].reshape(3, 3)
            mujoco.mju_mulMatVec(force[i], rotation, measurement.force_in_sensor[i])
            mujoco.mju_mulMatVec(moment[i], rotation, measurement.moment_in_sensor[i])
            fz = float(force[i, 2])
            self.force_z_n[i] = fz
            if fz >= self.threshold_n:
                total += fz
                if planned_yaw is not None:
                    xmat = data.site_xmat[sole]
                    yaw = math.atan2(float(xmat[3]), float(xmat[0]))
                    turn += fz * ((float(planned_yaw[i]) - yaw + math.pi) % _TWO_PI - math.pi)
        if turn != 0.0 and total > 0.0:
            self._turn(turn / total)
        anchor = self._anchor
        anchor[:] = 0.0
        if total > 0.0:
            for i, sole in enumerate(self._sole):
                fz = float(self.force_z_n[i])
                if fz >= self.threshold_n:
                    anchor += fz * (planned_soles[i] - data.site_xpos[sole])
        if total > 0.0:
            np.multiply(anchor, 1.0 / total, out=self._offset)
        np.add(data.site_xpos[self._sensor], self._offset, out=self._origin)
        com = self._com
        np.add(data.subtree_com[1], self._offset, out=com)
        if self._started:
            blend, velocity = self._blend, self.com_velocity_in_world
            for axis in range(3):
                rate = (com[axis] - self.com_in_world[axis]) / self.period_s
                velocity[axis] += blend * (rate - velocity[axis])
        self._started = True
        self.com_in_world[:] = com
        zmp = zmp_in_world_now(force, moment, self._origin, self.threshold_n)
        if zmp is None:
            self.zmp_in_world[:] = np.nan
        else:
            self.zmp_in_world[0], self.zmp_in_world[1] = zmp
