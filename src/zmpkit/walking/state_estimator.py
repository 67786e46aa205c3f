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
(:func:`zmpkit.sensors.zmp_now.zmp_in_world_now`). The CoM velocity is that of the CoM
relative to the feet in contact, each of which stands still on the floor, weighted as the
anchor and low-passed with time constant ``τ_v``:

.. math:: \dot c_k = \frac{\sum_i F_{z,i} \left[(c_{fk} - s_i)_k - (c_{fk} - s_i)_{k-1}\right]}
    {T \sum_i F_{z,i}}, \qquad
    \hat v \leftarrow \hat v + \frac{T}{τ_v + T}\left(\dot c_k - \hat v\right).

It is not the finite difference of ``\hat c``: while the weight moves from one foot to a foot
that landed a few millimetres from its plan, the anchor ``Δ`` moves by those millimetres
within a few ticks, and its rate (up to 0.4 m/s at a touchdown after a push on a 3 kg
humanoid, 0.1 m/s in its unpushed walk: the DCM ``\hat c + \hat v/ω`` off by up to 6 cm) is
no motion of the robot. Without a foot in contact the finite difference of ``\hat c`` is
used.

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

A tick is real-time code: :meth:`KinematicStateEstimator.update` writes into arrays and views
made at construction (``np.dot(..., out=)`` for the rotations, ``ndarray.put`` for the
encoders, Python floats read and written element by element for the rest), so it creates no
numpy array, view or scalar and keeps nothing (``tests/walking/test_tick_allocations.py``).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ModelError
from zmpkit.sensors.zmp_now import zmp_in_world_now
from zmpkit.walking.measurement import WalkMeasurement

__all__ = ["KinematicStateEstimator"]

_TWO_PI = 2.0 * math.pi


def _site(model: mujoco.MjModel, name: str) -> int:
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
    if site < 0:
        raise ModelError(f"the design model has no site {name!r}")
    return int(site)


def _imu_in_base(
    model: mujoco.MjModel, imu_site: str
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The IMU frame's orientation in the base (a unit quaternion) and ``p ↦ p ⊗ it``.

    The second is the 4×4 matrix of the Hamilton product ``q ⊗ p = M(p) q``.

    Raises:
        ModelError: the IMU site is not on the root body.
    """
    imu = _site(model, imu_site)
    if int(model.site_bodyid[imu]) != 1:
        raise ModelError(f"the IMU site {imu_site!r} must be on the root body")
    imu_in_base = np.empty(4)
    mujoco.mju_negQuat(imu_in_base, model.site_quat[imu])  # conjugate
    a, b, c, d = imu_in_base.tolist()
    times = np.array([[a, -b, -c, -d], [b, a, d, -c], [c, -d, a, b], [d, c, -b, a]])
    return imu_in_base, times


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
        self._qadr = np.array([self._qpos_address(name) for name in joint_names], dtype=np.intp)
        self._coupled = self._coupled_joints(set(self._qadr.tolist()))
        self._sole = [_site(model, sole_sites[f]) for f in self.feet]
        self._sensor = [_site(model, sensor_sites[f]) for f in self.feet]
        self._imu_in_base, self._times_imu_in_base = _imu_in_base(model, imu_site)
        f = len(self.feet)
        self._force = np.zeros((f, 3))
        self._moment = np.zeros((f, 3))
        self._origin = np.zeros((f, 3))
        self._offset = np.zeros(3)
        self._com = np.zeros(3)
        self.com_in_world = np.zeros(3)
        """Estimated CoM [m], shape (3,)."""
        self.com_velocity_in_world = np.zeros(3)
        """Estimated CoM velocity [m/s], shape (3,)."""
        self.zmp_in_world = np.full(2, np.nan)
        """Estimated ZMP on the floor [m], shape (2,); NaN without contact."""
        self.force_z_n = np.zeros(f)
        """Each foot's vertical force in the world [N], shape (F,)."""
        self._relative_before = np.zeros((f, 3))  # c_fk - s_i of the last tick [m]
        self._started = False
        self.yaw_correction_rad = 0.0
        """The turn last applied to the IMU's yaw from the feet [rad]."""
        self._make_views()

    def _make_views(self) -> None:
        """The views of :attr:`data` a tick reads and writes, made once (no array per tick)."""
        data, f = self.data, len(self.feet)
        self._qpos = data.qpos
        self._base_position = data.qpos[:3]
        self._base_quaternion = data.qpos[3:7]
        self._force_in_sensor = np.zeros((f, 3))
        self._moment_in_sensor = np.zeros((f, 3))
        self._rows = [  # per foot: its index and the views a tick reads and writes
            (
                i, data.site_xmat[sensor].reshape(3, 3), data.site_xmat[sole],
                data.site_xpos[sole], data.site_xpos[sensor],
                self._force[i], self._moment[i], self._origin[i],
                self._force_in_sensor[i], self._moment_in_sensor[i],
            )
            for i, (sole, sensor) in enumerate(zip(self._sole, self._sensor, strict=True))
        ]  # fmt: skip
        self._relative_rows = list(self._relative_before)  # one view a foot
        self._turned = [data.site_xpos[r] for r in (*self._sole, *self._sensor)]
        self._turned += [data.subtree_com[1], *self._force, *self._moment]
        self._root_com = data.subtree_com[1]

    def _turn(self, yaw: float) -> None:
        """Turn the whole posed robot by ``yaw`` [rad] about the vertical through its base."""
        c, s = math.cos(yaw), math.sin(yaw)
        for vector in self._turned:  # sole and sensor sites, the CoM, the wrenches
            x, y = vector.item(0), vector.item(1)
            vector[0] = c * x - s * y
            vector[1] = s * x + c * y
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

    def _anchor_offset(self, planned_soles: NDArray[np.float64], total: float) -> None:
        """Write the anchor offset Δ [m] of the feet in contact (module docstring).

        ``total`` is their Σ F_z [N] (> 0). Summed in Python floats: no array per tick.
        """
        threshold, force_z = self.threshold_n, self.force_z_n
        x = y = z = 0.0  # Σ F_z,i (ŝ_i - s_i)
        for row in self._rows:
            i, sole = row[0], row[3]
            fz = force_z.item(i)
            if fz >= threshold:
                x += fz * (planned_soles.item(i, 0) - sole.item(0))
                y += fz * (planned_soles.item(i, 1) - sole.item(1))
                z += fz * (planned_soles.item(i, 2) - sole.item(2))
        scale, offset = 1.0 / total, self._offset
        offset[0], offset[1], offset[2] = x * scale, y * scale, z * scale

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
        self._pose(measurement)
        total, turn = self._world_wrenches(measurement, planned_yaw)
        if turn != 0.0 and total > 0.0:
            self._turn(turn / total)
        if total > 0.0:  # else the offset is kept from the last tick with a foot in contact
            self._anchor_offset(planned_soles, total)
        offset = self._offset
        for row in self._rows:
            np.add(row[4], offset, out=row[7])  # sensor origin, anchored
        self._estimate_com()
        zmp = zmp_in_world_now(self._force, self._moment, self._origin, self.threshold_n)
        if zmp is None:
            self.zmp_in_world.fill(np.nan)
        else:
            self.zmp_in_world[0], self.zmp_in_world[1] = zmp

    def sole_in_world(self, foot: int, axis: int) -> float:
        """Where sole ``foot`` (index in :attr:`feet`) is now, along ``axis`` [m]: ``s_i + Δ``.

        A foot in contact is where the plan put it only if it landed there: this is where the
        estimate places it from the other feet in contact (leg odometry).
        """
        return self._rows[foot][3].item(axis) + self._offset.item(axis)

    def _pose(self, measurement: WalkMeasurement) -> None:
        """Pose the design model: the base at the origin turned by the IMU, the encoders."""
        data, model, qpos = self.data, self.model, self._qpos
        self._base_position.fill(0.0)
        np.dot(self._times_imu_in_base, measurement.imu_quaternion, out=self._base_quaternion)
        qpos.put(self._qadr, measurement.q_meas_rad)  # the encoders' joints
        for follower, leader, c0, c1 in self._coupled:
            qpos[follower] = c0 + c1 * qpos.item(leader)
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)

    def _world_wrenches(
        self, measurement: WalkMeasurement, planned_yaw: NDArray[np.float64] | None
    ) -> tuple[float, float]:
        """Each foot's wrench in the world frame; (Σ F_z [N], Σ F_z · yaw error [N·rad]).

        Both sums over the feet in contact; the yaw error (planned less posed sole heading)
        only with ``planned_yaw``.
        """
        np.copyto(self._force_in_sensor, measurement.force_in_sensor)
        np.copyto(self._moment_in_sensor, measurement.moment_in_sensor)
        threshold, force_z = self.threshold_n, self.force_z_n
        total = turn = 0.0
        for row in self._rows:
            i, rotation, sole_xmat, _, _, force, moment, _, f_sensor, m_sensor = row
            np.dot(rotation, f_sensor, out=force)  # R_i f_i, no temporaries
            np.dot(rotation, m_sensor, out=moment)
            fz = force.item(2)
            force_z[i] = fz
            if fz >= threshold:
                total += fz
                if planned_yaw is not None:
                    yaw = math.atan2(sole_xmat.item(3), sole_xmat.item(0))
                    turn += fz * ((planned_yaw.item(i) - yaw + math.pi) % _TWO_PI - math.pi)
        return total, turn

    def _estimate_com(self) -> None:
        """The CoM estimate (the model's, anchored) and its low-passed velocity (module doc)."""
        com = self._com
        np.add(self._root_com, self._offset, out=com)
        estimate, velocity = self.com_in_world, self.com_velocity_in_world
        rate_x, rate_y, rate_z, weight = self._relative_rate()
        if self._started:
            blend, period = self._blend, self.period_s
            if weight > 0.0:
                rate_x, rate_y, rate_z = rate_x / weight, rate_y / weight, rate_z / weight
            else:  # no foot in contact: the anchored estimate's own rate
                rate_x = (com.item(0) - estimate.item(0)) / period
                rate_y = (com.item(1) - estimate.item(1)) / period
                rate_z = (com.item(2) - estimate.item(2)) / period
            v_x, v_y, v_z = velocity.item(0), velocity.item(1), velocity.item(2)  # floats
            velocity[0] = v_x + blend * (rate_x - v_x)
            velocity[1] = v_y + blend * (rate_y - v_y)
            velocity[2] = v_z + blend * (rate_z - v_z)
        self._started = True
        np.copyto(estimate, com)

    def _relative_rate(self) -> tuple[float, float, float, float]:
        """Σ F_z,i of the CoM's velocity relative to each foot in contact, and Σ F_z,i.

        Each foot's ``c_fk - s_i`` is kept for the next tick, in contact or not.
        """
        root, threshold, force_z = self._root_com, self.threshold_n, self.force_z_n
        started, period = self._started, self.period_s
        x = y = z = weight = 0.0
        for row in self._rows:
            i, sole = row[0], row[3]
            before = self._relative_rows[i]
            rx = root.item(0) - sole.item(0)
            ry = root.item(1) - sole.item(1)
            rz = root.item(2) - sole.item(2)
            fz = force_z.item(i)
            if started and fz >= threshold:
                x += fz * (rx - before.item(0)) / period
                y += fz * (ry - before.item(1)) / period
                z += fz * (rz - before.item(2)) / period
                weight += fz
            before[0], before[1], before[2] = rx, ry, rz
        return x, y, z, weight
