"""Today's feedback tick, kept as the reference the allocation-free tick is tested against.

Verbatim copies (renamed) of :class:`~zmpkit.walking.state_estimator.KinematicStateEstimator`,
:class:`~zmpkit.walking.zmp_observer.ObservedPreviewControl`,
:class:`~zmpkit.walking.heading_feedback.HeadingFeedback` and
:func:`~zmpkit.sensors.zmp.zmp_in_world_now` as of commit 443946f, before their per-tick
numpy views and scalar temporaries were removed, with one change made to both since: the
estimator's CoM velocity is the CoM's relative to the loaded feet (not the finite difference
of the anchored estimate). ``tests/walking/test_tick_reference.py`` runs both on the same
recorded walk and asserts equal outputs.
"""

from __future__ import annotations

import math
from dataclasses import replace

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ModelError
from zmpkit.sensors.imu import quaternion_yaw
from zmpkit.walking.cart_table import PreviewGains
from zmpkit.walking.heading_feedback import HeadingFeedbackGains
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.swing import FeetTrajectories, swing_edges
from zmpkit.walking.zmp_observer import ZmpObserverParameters, observer_gain, observer_matrices

__all__ = ["ReferenceEstimator", "ReferenceHeading", "ReferenceObserver"]


def _reference_zmp_in_world_now(
    force_in_world: NDArray[np.float64],
    moment_in_world: NDArray[np.float64],
    sensor_in_world: NDArray[np.float64],
    contact_threshold_n: float,
) -> tuple[float, float] | None:
    """:func:`zmp_in_world` of one sample, in Python floats, for a control loop [m].

    The same equations over the feet in contact, without numpy temporaries (a few
    microseconds instead of a few hundred for two feet).

    Args:
        force_in_world: force of each foot [N], shape (F, 3).
        moment_in_world: moment about each sensor origin [N·m], shape (F, 3).
        sensor_in_world: sensor origins [m], shape (F, 3).
        contact_threshold_n: minimum world F_z for contact [N], > 0 (not checked here).

    Returns:
        The ZMP (x, y) [m], or None when no foot is in contact.
    """
    total = num_x = num_y = 0.0
    for i in range(force_in_world.shape[0]):  # element by element: no temporaries
        fz = force_in_world.item(i, 2)
        if fz >= contact_threshold_n:
            fx, fy = force_in_world.item(i, 0), force_in_world.item(i, 1)
            tx, ty = moment_in_world.item(i, 0), moment_in_world.item(i, 1)
            ox, oy, oz = (
                sensor_in_world.item(i, 0),
                sensor_in_world.item(i, 1),
                sensor_in_world.item(i, 2),
            )
            total += fz
            num_x += ox * fz - (ty + oz * fx)
            num_y += oy * fz + (tx - oz * fy)
    if total <= 0.0:
        return None
    return num_x / total, num_y / total


_TWO_PI = 2.0 * math.pi


def _site(model: mujoco.MjModel, name: str) -> int:
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
    if site < 0:
        raise ModelError(f"the design model has no site {name!r}")
    return int(site)


class ReferenceEstimator:
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
        a, b, c, d = self._imu_in_base.tolist()
        self._times_imu_in_base = np.array(  # q ⊗ p = M(p) q, the Hamilton product
            [[a, -b, -c, -d], [b, a, d, -c], [c, -d, a, b], [d, c, -b, a]]
        )
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
        self._relative_before = np.zeros((f, 3))  # c_fk - s_i of the last tick [m]
        self.yaw_correction_rad = 0.0
        """The turn last applied to the IMU's yaw from the feet [rad]."""
        # Views made once, so that a tick creates no array (module docstring of update).
        data = self.data
        self._qpos = data.qpos
        self._base_position = data.qpos[:3]
        self._base_quaternion = data.qpos[3:7]
        start = int(self._qadr[0]) if self._qadr.size else 0
        contiguous = np.array_equal(self._qadr, np.arange(start, start + self._qadr.size))
        self._joint_block = data.qpos[start : start + self._qadr.size] if contiguous else None
        self._joint_addresses = self._qadr.tolist()
        self._force_in_sensor = np.zeros((f, 3))
        self._moment_in_sensor = np.zeros((f, 3))
        self._rows = [
            (
                data.site_xmat[sensor].reshape(3, 3), data.site_xmat[sole],
                data.site_xpos[sole], data.site_xpos[sensor],
                self._force[i], self._moment[i], self._origin[i],
                self._force_in_sensor[i], self._moment_in_sensor[i],
            )
            for i, (sole, sensor) in enumerate(zip(self._sole, self._sensor, strict=True))
        ]  # fmt: skip
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
        data, model, qpos = self.data, self.model, self._qpos
        self._base_position.fill(0.0)
        np.dot(self._times_imu_in_base, measurement.imu_quaternion, out=self._base_quaternion)
        if self._joint_block is not None:
            np.copyto(self._joint_block, measurement.q_meas_rad)
        else:
            q_meas = measurement.q_meas_rad
            for j, address in enumerate(self._joint_addresses):
                qpos[address] = q_meas.item(j)
        for follower, leader, c0, c1 in self._coupled:
            qpos[follower] = c0 + c1 * qpos.item(leader)
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        np.copyto(self._force_in_sensor, measurement.force_in_sensor)
        np.copyto(self._moment_in_sensor, measurement.moment_in_sensor)
        threshold, force_z = self.threshold_n, self.force_z_n
        total = turn = 0.0
        for i, row in enumerate(self._rows):
            rotation, sole_xmat, _, _, force, moment, _, f_sensor, m_sensor = row
            np.dot(rotation, f_sensor, out=force)  # R_i f_i, no temporaries
            np.dot(rotation, m_sensor, out=moment)
            fz = force.item(2)
            force_z[i] = fz
            if fz >= threshold:
                total += fz
                if planned_yaw is not None:
                    yaw = math.atan2(sole_xmat.item(3), sole_xmat.item(0))
                    turn += fz * ((planned_yaw.item(i) - yaw + math.pi) % _TWO_PI - math.pi)
        if turn != 0.0 and total > 0.0:
            self._turn(turn / total)
        offset = self._offset  # kept from the last tick without a foot in contact
        if total > 0.0:
            anchor = self._anchor  # Σ F_z,i (ŝ_i - s_i)
            anchor.fill(0.0)
            for i, row in enumerate(self._rows):
                fz = force_z.item(i)
                if fz >= threshold:
                    sole_xpos = row[2]
                    for axis in range(3):
                        shift = planned_soles.item(i, axis) - sole_xpos.item(axis)
                        anchor[axis] = anchor.item(axis) + fz * shift
            np.multiply(anchor, 1.0 / total, out=offset)
        for row in self._rows:
            np.add(row[3], offset, out=row[6])  # sensor origin, anchored
        com = self._com
        np.add(self._root_com, offset, out=com)
        estimate, velocity = self.com_in_world, self.com_velocity_in_world
        relative = self._root_com[None, :] - np.array([row[2] for row in self._rows])
        loaded = force_z >= threshold
        if self._started:
            blend, period = self._blend, self.period_s
            weight = 0.0
            rates = [0.0, 0.0, 0.0]
            for i in np.flatnonzero(loaded):  # Σ F_z,i Δ(c - s_i) / T, foot after foot
                fz = float(force_z[i])
                for axis in range(3):
                    moved = float(relative[i, axis]) - float(self._relative_before[i, axis])
                    rates[axis] += fz * moved / period
                weight += fz
            for axis in range(3):
                if weight > 0.0:
                    rate = rates[axis] / weight
                else:
                    rate = (com.item(axis) - estimate.item(axis)) / period
                velocity[axis] += blend * (rate - velocity.item(axis))
        self._relative_before[:] = relative
        self._started = True
        np.copyto(estimate, com)
        zmp = _reference_zmp_in_world_now(self._force, self._moment, self._origin, threshold)
        if zmp is None:
            self.zmp_in_world.fill(np.nan)
        else:
            self.zmp_in_world[0], self.zmp_in_world[1] = zmp


class ReferenceObserver:
    """Preview control of both axes on the observed state (module docstring).

    Each period ``k``: correct the prior ``ẑ⁻_k`` with the measured CoM and ZMP, apply the
    preview law to the corrected state with the reference ``p^{ref} - d̂`` and the error sum
    of ``C_3 x̂ + d̂ - p^{ref}``, and predict ``ẑ⁻_{k+1}``, whose CoM is the next target.

    Args:
        gains: the preview gains of the cart table (:func:`compute_preview_gains`).
        zmp_reference_in_world: p^{ref} of every period [m], shape (N, 2); the preview
            window reads past the end as the last value.
        initial_state_in_world: rows x, y: CoM [m], velocity [m/s], acceleration [m/s²].
        parameters: the noise levels that set the observer's gain.
    """

    def __init__(
        self,
        gains: PreviewGains,
        zmp_reference_in_world: NDArray[np.float64],
        initial_state_in_world: NDArray[np.float64],
        parameters: ZmpObserverParameters | None = None,
    ) -> None:
        self.parameters = parameters or ZmpObserverParameters()
        p = gains.parameters
        self._a, self._b, self._c = observer_matrices(
            p.sampling_period_s, p.com_height_m, p.gravity_mps2
        )
        self.gain = observer_gain(
            self.parameters, p.sampling_period_s, p.com_height_m, p.gravity_mps2
        )
        self._gp = np.concatenate([[0.0], gains.preview_gains])
        self._gp_sum = float(self._gp.sum())
        self._g_i = float(gains.integral_gain)
        self._g_x = [float(g) for g in gains.state_gain]
        reference = np.asarray(zmp_reference_in_world, dtype=np.float64)
        self._n = reference.shape[0]
        padding = np.repeat(reference[-1:], self._gp.size, axis=0)
        self._reference = [  # per axis, contiguous, padded with the last value
            np.ascontiguousarray(np.concatenate([reference, padding])[:, axis]) for axis in (0, 1)
        ]
        self._l = self.gain.tolist()
        self._a3 = self._a[:3, :3].tolist()
        self._b3 = self._b[:3].tolist()
        self._zc_over_g = -float(self._c[1, 2])
        self.state = np.zeros((2, 4))
        """Prior of the next period, rows x, y: c [m], ċ [m/s], c̈ [m/s²], d [m]."""
        self.state[:, :3] = initial_state_in_world
        self._error_sum = np.zeros(2)
        self._y = np.zeros(2)
        self._dot = np.zeros(())  # the preview sum, written in place
        self.jerk_in_world = np.zeros(2)
        """The jerk of the last period, (x, y) [m/s³]."""

    @property
    def reference_by_axis(self) -> list[NDArray[np.float64]]:
        """p^{ref} of every period, one writable array per axis (x, y) [m].

        Padded past the walk's end with its last value. A compensation that adapts the
        reference online (paper B's Algorithm 2) writes the periods still to come here.
        """
        return self._reference

    @property
    def offset_in_world(self) -> NDArray[np.float64]:
        """The estimated ZMP offset d̂ (x, y) [m], a view."""
        return self.state[:, 3]

    def update(
        self, k: int, com_in_world: NDArray[np.float64], zmp_in_world: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """One period: correct with the measurements of period ``k`` and predict ``k + 1``.

        Args:
            k: the period the measurements belong to [-].
            com_in_world: the measured CoM (x, y) [m].
            zmp_in_world: the measured ZMP (x, y) [m]; NaN (no contact) skips the correction.

        Returns:
            The CoM (x, y) of period ``k + 1`` [m], a view of the prediction.
        """
        limit, k = self.parameters.max_offset_m, min(k, self._n - 1)
        clip = self.parameters.max_zmp_innovation_m
        size, l_gain, g_x, zc_g = self._gp.size, self._l, self._g_x, self._zc_over_g
        (a00, a01, a02), (_, a11, a12), (_, _, a22) = self._a3
        b0, b1, b2 = self._b3
        dot = self._dot
        for axis in (0, 1):
            z = self.state[axis]
            c, v, a, d = z.item(0), z.item(1), z.item(2), z.item(3)
            zmp = zmp_in_world.item(axis)
            if math.isfinite(zmp):
                e_c = com_in_world.item(axis) - c
                e_p = zmp - (c - zc_g * a + d)
                e_p = min(max(e_p, -clip), clip)
                c += l_gain[0][0] * e_c + l_gain[0][1] * e_p
                v += l_gain[1][0] * e_c + l_gain[1][1] * e_p
                a += l_gain[2][0] * e_c + l_gain[2][1] * e_p
                d += l_gain[3][0] * e_c + l_gain[3][1] * e_p
                d = min(max(d, -limit), limit)
            reference = self._reference[axis]
            np.dot(self._gp, reference[k : k + size], out=dot)  # Σ G_p(j) p^ref_{k+j}
            error_sum = self._error_sum.item(axis) + (c - zc_g * a + d - reference.item(k))
            self._error_sum[axis] = error_sum
            jerk = (
                -self._g_i * error_sum
                - (g_x[0] * c + g_x[1] * v + g_x[2] * a)
                - (dot.item() - d * self._gp_sum)
            )
            z[0] = a00 * c + a01 * v + a02 * a + b0 * jerk
            z[1] = a11 * v + a12 * a + b1 * jerk
            z[2] = a22 * a + b2 * jerk
            z[3] = d
            self.jerk_in_world[axis] = jerk
        return self.state[:, 0]


_SIDES = ("left", "right")


class ReferenceHeading:
    """Turns the feet still to land so that the IMU's heading follows the plan.

    Args:
        feet: the planned feet (left, right) and torso yaw; not changed.
        gains: K_ψ and c_max.

    Attributes:
        targets: the feet the IK follows: the plan's positions, yaw targets with the
            corrections (arrays of its own, written frame by frame).
        correction_rad: c, the current correction [rad].
        heading_error_rad: e at each lift-off [rad] (NaN elsewhere), shape (N,).
    """

    def __init__(self, feet: FeetTrajectories, gains: HeadingFeedbackGains | None = None) -> None:
        self.gains = gains or HeadingFeedbackGains()
        self._plan = feet
        self.targets = replace(
            feet,
            left=replace(feet.left, yaw_in_world=feet.left.yaw_in_world.copy()),
            right=replace(feet.right, yaw_in_world=feet.right.yaw_in_world.copy()),
            torso_yaw_in_world=feet.torso_yaw_in_world.copy(),
        )
        n = feet.time_s.size
        self._offset = {"left": np.zeros(n), "right": np.zeros(n)}
        self._lift_offs = {
            side: swing_edges(getattr(feet, side).in_contact) for side in ("left", "right")
        }
        self.correction_rad = 0.0
        self.heading_error_rad = np.full(n, np.nan)
        self._imu_start: float | None = None
        self._last_yaw = 0.0
        self._turns = 0.0
        self._error_sum = 0.0  # Σ e since the last lift-off [rad]
        self._error_frames = 0
        self._last_step_mean: float | None = None  # mean e over the step before [rad]
        self._ramp_shapes: dict[int, NDArray[np.float64]] = {}  # per swing length [frames]
        for lifts in self._lift_offs.values():
            for lift, land in lifts.items():
                swing = max(land - lift, 1)  # 0.5 - 0.5 cos(π j / n), j = 1..n
                shape = 0.5 - 0.5 * np.cos(np.pi * np.arange(1, swing + 1) / swing)
                self._ramp_shapes.setdefault(swing, shape)
        self._mean = np.zeros(n)

    def _imu_heading(self, quat_wxyz: NDArray[np.float64]) -> float:
        """The IMU's yaw since the first reading, unwrapped [rad]."""
        yaw = quaternion_yaw(quat_wxyz)
        if self._imu_start is None:
            self._imu_start, self._last_yaw = yaw, yaw
        step = (yaw - self._last_yaw + math.pi) % (2.0 * math.pi) - math.pi
        self._turns += step
        self._last_yaw = yaw
        return self._turns

    def update(self, frame: int, imu_quaternion: NDArray[np.float64]) -> None:
        """Read the IMU before ``frame``; at a lift-off, correct that foot's landing yaw."""
        if self.gains.gain_per_step == 0.0:
            return
        heading = self._imu_heading(imu_quaternion)
        plan = self._plan.torso_yaw_in_world
        now = heading - (plan.item(min(frame, plan.size - 1)) - plan.item(0))
        self._error_sum += now
        self._error_frames += 1
        for side in _SIDES:
            land = self._lift_offs[side].get(frame)
            if land is None:
                continue
            step_mean = self._error_sum / self._error_frames
            error = (
                step_mean
                if self._last_step_mean is None
                else (0.5 * (step_mean + self._last_step_mean))
            )  # the last two steps: one gait cycle, the torso's left-right sway cancels
            self._last_step_mean, self._error_sum, self._error_frames = step_mean, 0.0, 0
            self.heading_error_rad[frame] = error
            g = self.gains
            change = min(max(-g.gain_per_step * error, -g.max_change_per_step_rad),
                         g.max_change_per_step_rad)  # fmt: skip
            c = self.correction_rad + change
            self.correction_rad = min(max(c, -g.max_correction_rad), g.max_correction_rad)
            self._ramp(side, frame, land)

    def _ramp(self, side: str, lift: int, land: int) -> None:
        """This foot's offset: a cosine ramp to c over the swing, then c until the end.

        Written in place (the ramps' shapes are made with the plan).
        """
        offset = self._offset[side]
        start, goal = offset.item(lift), self.correction_rad
        n = max(land - lift, 1)
        shape = self._ramp_shapes[n]
        m = min(n, offset.size - lift)
        ramp = offset[lift : lift + m]
        np.multiply(shape[:m], goal - start, out=ramp)
        ramp += start
        offset[lift + m :] = goal
        plan, target = getattr(self._plan, side), getattr(self.targets, side)
        np.add(plan.yaw_in_world[lift:], offset[lift:], out=target.yaw_in_world[lift:])
        mean = self._mean[lift:]  # the torso turns by the feet's mean offset
        np.add(self._offset["left"][lift:], self._offset["right"][lift:], out=mean)
        mean *= 0.5
        torso = self.targets.torso_yaw_in_world[lift:]
        np.add(self._plan.torso_yaw_in_world[lift:], mean, out=torso)
