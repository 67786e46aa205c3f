"""Play a joint trajectory on a simulated robot.

Record what its sensors and a motion capture see.

The robot's motion frame (e.g. 10 ms) gives one IK solution per frame; its device manager
interpolates linearly between frames, so the servos get a new setpoint every physics step.
Recorded once per motion frame:

- commanded and measured (encoder) joint angles [rad] and the joint torques the actuators
  apply [N·m] (a real robot estimates these from its motor currents);
- trunk pitch and roll from the IMU's orientation [rad];
- each foot's F-T wrench rotated into the world frame, and the sensor's world position, from
  which the measured ZMP follows (:func:`zmpkit.sensors.zmp.zmp_in_world`);
- each sole centre's world position and the torso position: a motion capture of the robot.

A fall (trunk tilt beyond :data:`FALL_TILT_RAD`, or the torso below
:data:`FALL_TORSO_HEIGHT_FRACTION` of its height in the starting pose, whatever the robot's
size) stops the run; the record then ends at the fall and says which (``fall_kind``: ``roll``,
``pitch`` or ``height``).

A walking controller (:mod:`zmpkit.walking.walk_controllers`) reads, before each motion frame
``k``, the :class:`~zmpkit.walking.measurement.WalkMeasurement` of frame ``k - 1`` — encoders,
IMU and the F-T wrenches in their sensor frames, nothing else — and gives the joint targets
of frame ``k``. Paper B's Algorithm 2 enters the same way through ``frame_hook``, which gets
the :class:`FrameReading` of frame ``k - 1`` and returns the targets of frame ``k`` (or None to
keep the controller's). With neither, the planned trajectory is played unchanged.

Pushes and sensor faults (:mod:`zmpkit.experiments.walk_disturbances`) disturb the walk: a
push is a force on the torso, a fault corrupts what the controller reads, never the record.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.walk_disturbances import Push, SensorFault, TorsoPusher
from zmpkit.sensors.imu import quaternion_pitch_roll, quaternion_yaw
from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sim.names import sole_site
from zmpkit.sim.world import Simulation
from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.step_events import StepEvent
from zmpkit.walking.walk_controllers import WalkController

__all__ = [
    "FALL_TILT_RAD",
    "FALL_TORSO_HEIGHT_FRACTION",
    "FrameHook",
    "FrameReading",
    "ProgressCallback",
    "WalkRecord",
    "WalkSensors",
    "simulate_walk",
    "start_pose",
]

FALL_TILT_RAD = 0.8
"""Trunk tilt (pitch or roll) beyond which the robot has fallen [rad]."""
FALL_TORSO_HEIGHT_FRACTION = 0.6
"""Share of its starting height below which the torso has fallen [-] (the built-in walker's
absolute 0.18 m of its 0.30 m, scaled with the robot)."""
PROGRESS_EVERY_S = 0.5
"""Simulated time between two progress reports [s]."""

ProgressCallback = Callable[[float, float], None]
"""``progress(simulated_s, total_s)``, called during a run."""


@dataclass(frozen=True)
class FrameReading:
    """What the robot's sensors read at one motion frame (views, valid during the hook call).

    Attributes:
        frame: index of the frame [-].
        time_s: its time [s].
        force_in_world: F-T force of each foot in the world frame [N], shape (F, 3).
        moment_in_world: F-T moment about each sensor, world frame [N·m], shape (F, 3).
        sensor_in_world: F-T sensor origins [m], shape (F, 3).
        contact_threshold_n: the robot's contact threshold [N] (:mod:`zmpkit.sensors.zmp`).
        trunk_yaw_rad: IMU yaw, unwrapped [rad], shape (N,); None in records made without it.
    """

    frame: int
    time_s: float
    force_in_world: NDArray[np.float64]
    moment_in_world: NDArray[np.float64]
    sensor_in_world: NDArray[np.float64]
    contact_threshold_n: float

    def zmp_in_world(self) -> NDArray[np.float64]:
        """The measured ZMP of this frame [m], shape (2,); NaN without contact."""
        return zmp_in_world(
            self.force_in_world[None], self.moment_in_world[None], self.sensor_in_world[None],
            self.contact_threshold_n,
        )[0]  # fmt: skip


FrameHook = Callable[[int, FrameReading], "NDArray[np.float64] | None"]
"""``hook(k, reading_of_frame_k_minus_1)`` -> joint targets of frame k [rad], or None."""


@dataclass(frozen=True)
class WalkSensors:
    """The raw readings of every frame, as the sensors give them (a robot's log).

    Attributes:
        imu_quat_wxyz: IMU orientation (w, x, y, z) [-], shape (N, 4).
        gyro_rps: gyro, IMU frame [rad/s], shape (N, 3).
        accel_mps2: accelerometer, IMU frame [m/s²], shape (N, 3).
        ft_wrench: each foot's wrench in its sensor frame, ``record.feet`` order
            [N, N·m], shape (N, F, 6).
    """

    imu_quat_wxyz: NDArray[np.float64]
    gyro_rps: NDArray[np.float64]
    accel_mps2: NDArray[np.float64]
    ft_wrench: NDArray[np.float64]


@dataclass(frozen=True)
class WalkRecord:
    """Signals of one simulated walk, one row per motion frame.

    Attributes:
        time_s: [s], shape (N,).
        joint_names: the driven joints, columns of the joint arrays.
        q_cmd_rad: commanded joint angles [rad], shape (N, J).
        q_meas_rad: encoder joint angles [rad], shape (N, J).
        torque_nm: actuator torque at each joint [N·m], shape (N, J).
        trunk_pitch_rad: IMU pitch (nose down positive) [rad], shape (N,).
        trunk_roll_rad: IMU roll [rad], shape (N,).
        feet: foot names, in the order of the foot arrays.
        force_in_world: F-T force of each foot in the world frame [N], shape (N, F, 3).
        moment_in_world: F-T moment about the sensor, world frame [N·m], shape (N, F, 3).
        sensor_in_world: F-T sensor origin [m], shape (N, F, 3).
        sole_in_world: sole-centre position [m], shape (N, F, 3).
        torso_in_world: torso origin [m], shape (N, 3).
        fell: whether the robot fell.
        fall_time_s: when, or None.
        fall_kind: how (``roll``, ``pitch``, ``height``), or None.
        controller: the walking controller that ran.
        qpos: the simulator's whole configuration (MuJoCo ``qpos``), shape (N, nq); for
            validating models against the simulation, not something a real robot reports.
        contact_threshold_n: the robot's contact threshold [N] (:mod:`zmpkit.sensors.zmp`).
        trunk_yaw_rad: IMU yaw, unwrapped [rad], shape (N,); None in records made without it.
        step_events: the steps the controller adjusted to capture its DCM, and whether they
            could (:class:`~zmpkit.walking.step_adjustment.StepEvent`).
        sensors: the raw IMU and F-T readings of every frame (what a robot's log holds);
            None in records made without them.
    """

    time_s: NDArray[np.float64]
    joint_names: tuple[str, ...]
    q_cmd_rad: NDArray[np.float64]
    q_meas_rad: NDArray[np.float64]
    torque_nm: NDArray[np.float64]
    trunk_pitch_rad: NDArray[np.float64]
    trunk_roll_rad: NDArray[np.float64]
    feet: tuple[str, ...]
    force_in_world: NDArray[np.float64]
    moment_in_world: NDArray[np.float64]
    sensor_in_world: NDArray[np.float64]
    sole_in_world: NDArray[np.float64]
    torso_in_world: NDArray[np.float64]
    fell: bool
    fall_time_s: float | None
    qpos: NDArray[np.float64] | None
    contact_threshold_n: float
    fall_kind: str | None = None
    controller: str = "open"
    trunk_yaw_rad: NDArray[np.float64] | None = None
    step_events: tuple[StepEvent, ...] = ()
    sensors: WalkSensors | None = None

    def zmp_in_world(self) -> NDArray[np.float64]:
        """The measured ZMP from the feet's F-T sensors [m], shape (N, 2); NaN without contact."""
        return zmp_in_world(
            self.force_in_world, self.moment_in_world, self.sensor_in_world,
            self.contact_threshold_n,
        )  # fmt: skip

    def in_contact(self) -> NDArray[np.bool_]:
        """Whether each foot touches the floor, shape (N, F) (the ZMP's contact rule)."""
        return self.force_in_world[..., 2] >= self.contact_threshold_n

    def joint(self, name: str) -> int:
        """Column of joint ``name``."""
        return self.joint_names.index(name)


def start_pose(sim: Simulation, trajectory: JointTrajectory) -> list[float]:
    """Place the robot in the trajectory's first pose at rest; return the servo targets."""
    data, model = sim.data, sim.model
    data.qpos[:7] = trajectory.base_qpos[0]
    data.qvel[:] = 0.0
    for name, angle in zip(trajectory.joint_names, trajectory.q_rad[0], strict=True):
        data.qpos[int(model.joint(name).qposadr[0])] = angle
    q0 = [float(trajectory.q_rad[0, trajectory.joint_names.index(j)]) for j in sim.joint_names]
    sim.servo.reset(q0)
    sim.command(q0)
    sim.step(1)
    return q0


class _Recorder:
    """Collects one row per motion frame."""

    def __init__(self, sim: Simulation, n: int, feet: tuple[str, ...]) -> None:
        self.sim, self.feet = sim, feet
        j, f = len(sim.joint_names), len(feet)
        self.dof = [int(sim.model.joint(name).dofadr[0]) for name in sim.joint_names]
        self.rows = 0
        self.time = np.zeros(n)
        self.q_cmd, self.q_meas, self.torque = np.zeros((n, j)), np.zeros((n, j)), np.zeros((n, j))
        self.pitch, self.roll, self.yaw = np.zeros(n), np.zeros(n), np.zeros(n)
        self.force, self.moment = np.zeros((n, f, 3)), np.zeros((n, f, 3))
        self.sensor, self.sole = np.zeros((n, f, 3)), np.zeros((n, f, 3))
        self.torso = np.zeros((n, 3))
        self.qpos = np.zeros((n, sim.model.nq))
        self.imu = np.zeros((n, 10))  # gyro, accelerometer, quaternion
        self.wrench = np.zeros((n, f, 6))

    def record(self, q_cmd: NDArray[np.float64]) -> tuple[float, float]:
        sim, k = self.sim, self.rows
        data = sim.data
        self.time[k] = sim.time
        self.q_cmd[k], self.q_meas[k] = q_cmd, sim.encoders()
        self.torque[k] = data.qfrc_actuator[self.dof]
        gyro, accel, orientation = sim.imu()
        self.imu[k] = np.concatenate((gyro, accel, orientation))
        self.pitch[k], self.roll[k] = quaternion_pitch_roll(orientation)
        self.yaw[k] = quaternion_yaw(orientation)
        for i, foot in enumerate(self.feet):
            sensor = next(f for f in sim.robot.feet if f.foot == foot)
            site = data.site(sensor.site)
            self.wrench[k, i] = sim.ft(foot)
            self.force[k, i], self.moment[k, i] = wrench_in_world(site.xmat, self.wrench[k, i])
            self.sensor[k, i] = site.xpos
            self.sole[k, i] = data.site(sole_site(foot)).xpos
        self.torso[k] = data.qpos[:3]
        self.qpos[k] = data.qpos
        self.rows += 1
        return self.pitch[k], self.roll[k]

    def result(
        self, fall_kind: str | None, controller: str, events: tuple[StepEvent, ...] = ()
    ) -> WalkRecord:
        n = self.rows
        fall_time = float(self.time[n - 1]) if fall_kind is not None else None
        imu = self.imu[:n]
        sensors = WalkSensors(imu[:, 6:], imu[:, :3], imu[:, 3:6], self.wrench[:n])
        return WalkRecord(
            self.time[:n], self.sim.joint_names, self.q_cmd[:n], self.q_meas[:n],
            self.torque[:n], self.pitch[:n], self.roll[:n], self.feet, self.force[:n],
            self.moment[:n], self.sensor[:n], self.sole[:n], self.torso[:n],
            fall_kind is not None, fall_time, self.qpos[:n],
            self.sim.robot.contact_force_threshold_n, fall_kind, controller,
            np.unwrap(self.yaw[:n]), events, sensors,
        )  # fmt: skip

    def reading(self) -> FrameReading:
        """The last recorded frame."""
        k = self.rows - 1
        return FrameReading(
            k, float(self.time[k]), self.force[k], self.moment[k], self.sensor[k],
            self.sim.robot.contact_force_threshold_n,
        )  # fmt: skip


def _fall_kind(sim: Simulation, pitch: float, roll: float, fall_height_m: float) -> str | None:
    """``roll`` or ``pitch`` past :data:`FALL_TILT_RAD`, ``height``, or None.

    ``height``: the torso is below ``fall_height_m`` [m].
    """
    if max(abs(pitch), abs(roll)) > FALL_TILT_RAD:
        return "roll" if abs(roll) >= abs(pitch) else "pitch"
    if float(sim.data.qpos[2]) < fall_height_m:
        return "height"
    return None


def read_measurement(sim: Simulation, measurement: WalkMeasurement) -> None:
    """Fill ``measurement`` with what the robot's sensors read now (encoders, IMU, F-T)."""
    measurement.time_s = sim.time
    measurement.q_meas_rad[:] = sim.encoders()
    gyro, _, quaternion = sim.imu()
    measurement.gyro_rps[:] = gyro
    measurement.imu_quaternion[:] = quaternion
    for i, foot in enumerate(measurement.feet):
        wrench = sim.ft(foot)
        measurement.force_in_sensor[i] = wrench[:3]
        measurement.moment_in_sensor[i] = wrench[3:]


def simulate_walk(
    sim: Simulation,
    trajectory: JointTrajectory,
    progress: ProgressCallback | None = None,
    frame_hook: FrameHook | None = None,
    controller: WalkController | None = None,
    pushes: Sequence[Push] = (),
    faults: Sequence[SensorFault] = (),
) -> WalkRecord:
    """Track ``trajectory`` with the simulated robot's servos from its first pose.

    Args:
        sim: a fresh simulation of the robot (its driven joints must be in the trajectory).
        trajectory: joint angles per motion frame, from :func:`~zmpkit.walking.ik.solve_walking_ik`.
        progress: called with (simulated time, total time) [s] every half second of walk.
        frame_hook: online controller that may replace each frame's joint targets (module
            docstring); None plays ``trajectory`` as planned.
        controller: the walking controller (module docstring); None plays ``trajectory``.
        pushes: forces on the torso during the walk.
        faults: sensor faults the controller meets.

    Returns:
        The record, ending at the fall if the robot fell.
    """
    columns = [trajectory.joint_names.index(j) for j in sim.joint_names]
    q_frames = trajectory.q_rad[:, columns]
    frame_s = float(trajectory.time_s[1] - trajectory.time_s[0])
    substeps = max(1, round(frame_s / sim.dt))
    feet = tuple(f.foot for f in sim.robot.feet)
    recorder = _Recorder(sim, len(q_frames), feet)
    measurement = WalkMeasurement.empty(sim.joint_names, feet)
    pusher = TorsoPusher(sim, pushes)
    start_pose(sim, trajectory)
    fall_height_m = FALL_TORSO_HEIGHT_FRACTION * float(sim.data.qpos[2])
    recorder.record(q_frames[0])
    total = float(trajectory.time_s[-1])
    every = max(1, round(PROGRESS_EVERY_S / frame_s))
    name = "open" if controller is None else controller.name
    if frame_hook is not None or controller is not None:
        q_frames = q_frames.copy()
    for k in range(1, len(q_frames)):
        if controller is not None:
            q_frames[k] = _controlled(sim, controller, k, measurement, faults, frame_s)[columns]
        if frame_hook is not None:
            online = frame_hook(k, recorder.reading())
            if online is not None:
                q_frames[k] = np.asarray(online, dtype=np.float64)[columns]
        step = (q_frames[k] - q_frames[k - 1]) / substeps
        for i in range(1, substeps + 1):
            sim.command(q_frames[k - 1] + i * step)
            pusher.apply()
            sim.step(1)
        pitch, roll = recorder.record(q_frames[k])
        kind = _fall_kind(sim, pitch, roll, fall_height_m)
        if kind is not None:
            return recorder.result(kind, name, _step_events(controller))
        if progress is not None and k % every == 0:
            progress(sim.time, total)
    return recorder.result(None, name, _step_events(controller))


def _controlled(
    sim: Simulation,
    controller: WalkController,
    k: int,
    measurement: WalkMeasurement,
    faults: Sequence[SensorFault],
    frame_s: float,
) -> NDArray[np.float64]:
    """``controller``'s joint targets of frame ``k`` [rad] from what the robot reads now."""
    if controller.reads_sensors:
        read_measurement(sim, measurement)
        for fault in faults:
            fault.apply(measurement, frame_s)
    return controller.step(k, measurement)


def _step_events(controller: WalkController | None) -> tuple[StepEvent, ...]:
    """The steps ``controller`` adjusted (none for a controller that does not step)."""
    events = getattr(controller, "step_events", None)
    return () if events is None else tuple(events())
