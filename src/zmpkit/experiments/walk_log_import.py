"""A walk log from a robot's own recording: a ROS 2 bag or YARP dumps.

A real robot records its streams apart, each on its own clock and rate: both feet's
wrenches, the joint encoders (a ``sensor_msgs/JointState`` topic, or controlboard
``state:o`` ports), the joint commands its controller sent (a second JointState topic, or
the ports where the commands were dumped) and the IMU. :func:`walk_log_from_source` reads
them with :func:`~zmpkit.io.read_robot_source` (units and frames applied as given) and puts
them on the encoders' clock, which is the clock the fit compares joints on
(:mod:`zmpkit.simfit.shooting`):

- the rows are the encoder samples inside the span every stream covers (no extrapolation);
- wrenches, gyro and accelerometer are interpolated linearly, the orientation by nlerp
  (:func:`~zmpkit.io.resample.resample`, whose gap rule applies);
- a command is held from its stamp until the next one (zero-order hold): a servo tracks the
  last setpoint it received, so no command is invented between two that were sent.

The IMU's orientation must be logged (the fit places the robot by it) and is taken as the
IMU frame's orientation in a gravity-aligned world frame (ROS REP 145); a stream without
it, an encoder stream missing a commanded joint, or streams that do not overlap are errors
naming the source and topic.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from zmpkit.errors import InputFileError
from zmpkit.experiments.walk_log import WalkLog
from zmpkit.io import read_robot_source
from zmpkit.io.log_units import LogUnits
from zmpkit.io.resample import resample
from zmpkit.io.robot_log import JointLog, RobotLog

__all__ = ["walk_log_from_source"]


def walk_log_from_source(
    path: str | Path,
    *,
    right_topic: str | None = None,
    left_topic: str | None = None,
    joint_topic: str | Sequence[str],
    command_topic: str | Sequence[str],
    imu_topic: str,
    joint_names: Sequence[str] | None = None,
    units: LogUnits | str | Path | None = None,
    time_source: str = "header",
    max_gap_s: float | None = None,
) -> WalkLog:
    """The walk log of a robot's recording, on its encoders' clock (module docstring).

    Args:
        path: a ROS 2 bag (folder, ``.db3``, ``.mcap``) or a folder of YARP dumps.
        right_topic: the right foot's wrench topic or port (YARP: its default if None).
        left_topic: the left foot's wrench topic or port.
        joint_topic: the encoders: a JointState topic, or YARP ``state:o`` port(s).
        command_topic: the commands: a JointState topic whose ``position`` is the commanded
            angle, or YARP port(s) dumping them in the same layout as ``joint_topic``.
        imu_topic: the IMU's Imu topic or inertial port (with orientation).
        joint_names: YARP only: one name per joint value of the ports, in order (the same
            names for the encoder and the command ports).
        units: units and frames of the raw values (:class:`~zmpkit.io.log_units.LogUnits`
            or its YAML); None: already SI.
        time_source: ``"header"`` (sensor stamps) or ``"receive"``.
        max_gap_s: longest gap [s] interpolated across; None: the resampler's default.

    Raises:
        InputFileError: a stream missing or without what the log needs, or streams that do
            not overlap, naming the source.
        ParameterError: an option the source does not take.
    """
    path = Path(path)

    def read(joints: str | Sequence[str], imu: str | None) -> RobotLog:
        return read_robot_source(
            path, right_topic=right_topic, left_topic=left_topic, joint_topic=joints,
            imu_topic=imu, joint_names=joint_names, units=units, time_source=time_source,
            max_gap_s=max_gap_s,
        )  # fmt: skip

    log = read(joint_topic, imu_topic)
    commanded = read(command_topic, None)
    if log.joints is None or commanded.joints is None:
        raise InputFileError(path, "has no joint stream: give the encoder and command topics")
    if log.imu is None or log.imu.orientation_xyzw is None:
        raise InputFileError(
            path, f"the IMU stream {imu_topic!r} has no orientation; a walk log needs it"
        )
    shift_s = (commanded.time_origin_ns - log.time_origin_ns) * 1e-9
    commands = commanded.joints
    command_time = commands.time + shift_s
    joints = _commanded_joints(path, log.joints, commands)
    rows = _rows(path, log, command_time)
    aligned = resample(log, time=rows, max_gap_s=max_gap_s)
    assert aligned.joints is not None
    assert aligned.imu is not None
    assert aligned.imu.orientation_xyzw is not None
    held = np.searchsorted(command_time, rows, side="right") - 1
    encoder_columns = [aligned.joints.names.index(j) for j in joints]
    command_columns = [commands.names.index(j) for j in joints]
    return WalkLog(
        rows,
        joints,
        commands.position[held][:, command_columns],
        aligned.joints.position[:, encoder_columns],
        aligned.imu.orientation_xyzw[:, [3, 0, 1, 2]],
        aligned.imu.angular_velocity,
        aligned.ft.right_wrench,
        aligned.ft.left_wrench,
        aligned.imu.linear_acceleration,
        str(path),
    )


def _commanded_joints(path: Path, encoders: JointLog, commands: JointLog) -> tuple[str, ...]:
    """The commanded joints, each of which the encoders must read."""
    unread = [j for j in commands.names if j not in encoders.names]
    if unread:
        raise InputFileError(
            path,
            f"the commanded joints {unread[:4]} have no encoder in {encoders.source or 'it'}; "
            f"encoders: {list(encoders.names)[:8]}",
        )
    return commands.names


def _rows(path: Path, log: RobotLog, command_time: np.ndarray) -> np.ndarray:
    """The encoder times inside the span of every stream (commands from their first)."""
    assert log.joints is not None
    assert log.imu is not None
    spans = {
        "feet": log.ft.time,
        "IMU": log.imu.time,
        "commands": command_time,
        "encoders": log.joints.time,
    }
    start = max(float(t[0]) for t in spans.values())
    end = min(float(t[-1]) for t in spans.values() if t is not command_time)
    time = log.joints.time
    rows = time[(time >= start) & (time <= end)]
    if rows.size < 2:
        covered = ", ".join(f"{k} {t[0]:.3f}…{t[-1]:.3f} s" for k, t in spans.items())
        raise InputFileError(path, f"its streams do not overlap: {covered}")
    return np.asarray(rows, dtype=np.float64)
