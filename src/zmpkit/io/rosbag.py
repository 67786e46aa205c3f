"""ROS 2 bags (sqlite3 ``.db3`` and MCAP storage) through ``rosbags``.

Read: one ``geometry_msgs/msg/WrenchStamped`` topic per foot, and optionally a
``sensor_msgs/msg/JointState`` and a ``sensor_msgs/msg/Imu`` topic, each chosen by name.

Times: by default each message's ``header.stamp`` (when the sensor sampled it); with
``time_source="receive"`` the time the recorder received it (the bag's own timestamp). All
streams share one origin, the earliest first stamp among the topics read
(:attr:`~zmpkit.io.robot_log.RobotLog.time_origin_ns`), and are converted to seconds after
subtracting it in integer nanoseconds, so no precision is lost to the epoch. The two feet are
joined by :func:`~zmpkit.io.resample.merge_feet`. Values are taken as they are in the
messages (ROS uses N, N·m, rad, rad/s, m/s²); apply :class:`~zmpkit.io.log_units.LogUnits`
for anything else.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Protocol, cast

from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.resample import merge_feet
from zmpkit.io.robot_log import ImuLog, JointLog, RobotLog
from zmpkit.io.rosbag_messages import TopicData, imu_arrays, joint_arrays, wrench_array

__all__ = [
    "IMU_TYPE",
    "JOINT_STATE_TYPE",
    "TIME_SOURCES",
    "WRENCH_STAMPED_TYPE",
    "list_bag_topics",
    "read_ros2_bag",
]

WRENCH_STAMPED_TYPE = "geometry_msgs/msg/WrenchStamped"
JOINT_STATE_TYPE = "sensor_msgs/msg/JointState"
IMU_TYPE = "sensor_msgs/msg/Imu"
TIME_SOURCES = ("header", "receive")
"""``header``: ``header.stamp`` of each message; ``receive``: the bag's receive time."""


def _one_line(exc: BaseException, limit: int = 120) -> str:
    """A library's error as one short line: whitespace collapsed, cut to ``limit`` characters."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= limit else text[: limit - 3] + "..."


def read_ros2_bag(
    path: str | Path,
    *,
    right_topic: str,
    left_topic: str,
    joint_topic: str | None = None,
    imu_topic: str | None = None,
    time_source: str = "header",
    max_gap_s: float | None = None,
) -> RobotLog:
    """Read both feet's wrenches (and joint states, IMU) from a ROS 2 bag.

    Args:
        path: a bag folder (with ``metadata.yaml``), or one ``.db3`` or ``.mcap`` file.
        right_topic: the right foot's WrenchStamped topic, e.g. ``/ft/right``.
        left_topic: the left foot's WrenchStamped topic.
        joint_topic: a JointState topic, or None.
        imu_topic: an Imu topic, or None.
        time_source: "header" (default) or "receive", see :data:`TIME_SOURCES`.
        max_gap_s: longest gap [s] the left foot is interpolated across when the feet do not
            share stamps (:func:`~zmpkit.io.resample.merge_feet`).

    Returns:
        The log: wrenches [N, N·m] in each sensor's frame, times [s] from the common origin.

    Raises:
        InputFileError: unreadable bag; missing topic (the topics present are listed with
            their types); wrong message type; empty topic; stamps not strictly increasing;
            NaN or infinite values — each naming the bag and topic.
    """
    if time_source not in TIME_SOURCES:
        raise ParameterError(
            f"time_source must be one of {', '.join(TIME_SOURCES)}, got {time_source!r}"
        )
    path = Path(path)
    wanted = {right_topic: WRENCH_STAMPED_TYPE, left_topic: WRENCH_STAMPED_TYPE}
    for topic, msgtype in ((joint_topic, JOINT_STATE_TYPE), (imu_topic, IMU_TYPE)):
        if topic is not None:
            wanted[topic] = msgtype
    data = _read_topics(path, wanted, time_source == "header")
    origin = min(int(d.stamps_ns[0]) for d in data.values())
    right, left = data[right_topic], data[left_topic]
    ft = merge_feet(
        right.seconds(origin),
        wrench_array(path, right),
        left.seconds(origin),
        wrench_array(path, left),
        source=f"{path} ({right_topic}, {left_topic})",
        max_gap_s=max_gap_s,
    )
    joints = _joint_log(path, data[joint_topic], origin) if joint_topic else None
    imu = _imu_log(path, data[imu_topic], origin) if imu_topic else None
    return RobotLog(ft=ft, joints=joints, imu=imu, time_origin_ns=origin, source=str(path))


def _open(path: Path) -> Reader:
    try:
        reader = Reader(path)
        reader.open()
    except FileNotFoundError:
        raise InputFileError(
            path, "not found; expected a ROS 2 bag folder, .db3 or .mcap file"
        ) from None
    except Exception as exc:  # rosbags raises many kinds on a damaged bag
        raise InputFileError(path, f"cannot be opened as a ROS 2 bag ({_one_line(exc)})") from None
    return reader


def _read_topics(path: Path, wanted: dict[str, str], use_header: bool) -> dict[str, TopicData]:
    reader = _open(path)
    try:
        _check_topics(path, reader, wanted)
        data = _collect(path, reader, wanted, use_header)
    finally:
        reader.close()
    for d in data.values():
        d.check_stamps(path, "header" if use_header else "receive")
    return data


def _check_topics(path: Path, reader: Reader, wanted: dict[str, str]) -> None:
    topics = reader.topics
    for topic, msgtype in wanted.items():
        info = topics.get(topic)
        if info is None:
            present = ", ".join(f"{t} ({i.msgtype})" for t, i in sorted(topics.items()))
            raise InputFileError(
                path,
                f"topic '{topic}' not found; expected a {msgtype} topic; "
                f"the bag has: {present or 'no topics'}",
            )
        if info.msgtype != msgtype:
            raise InputFileError(
                path, f"topic '{topic}' has message type {info.msgtype}; expected {msgtype}"
            )
        if info.msgcount == 0:
            raise InputFileError(path, f"topic '{topic}' has no messages; expected at least one")


class _Time(Protocol):
    sec: int
    nanosec: int


class _Header(Protocol):
    stamp: _Time


class _StampedMessage(Protocol):
    """What is read of every message here: its std_msgs/Header (WrenchStamped, JointState, Imu)."""

    header: _Header


def _collect(
    path: Path, reader: Reader, wanted: dict[str, str], use_header: bool
) -> dict[str, TopicData]:
    typestore = get_typestore(Stores.LATEST)
    data = {topic: TopicData(topic) for topic in wanted}
    connections = [c for c in reader.connections if c.topic in wanted]
    try:
        for connection, receive_ns, raw in reader.messages(connections=connections):
            # rosbags builds the message classes at run time: its deserializer returns object
            msg = cast(_StampedMessage, typestore.deserialize_cdr(raw, connection.msgtype))
            stamp = msg.header.stamp
            ns = stamp.sec * 1_000_000_000 + stamp.nanosec if use_header else receive_ns
            data[connection.topic].append(ns, msg)
    except Exception as exc:  # corrupt storage or message bytes
        raise InputFileError(
            path, f"cannot read its messages ({_one_line(exc)}); the bag may be truncated"
        ) from None
    for topic, d in data.items():
        if not d.messages:
            raise InputFileError(path, f"topic '{topic}' has no messages; expected at least one")
    return data


def _joint_log(path: Path, data: TopicData, origin: int) -> JointLog:
    names, position, velocity = joint_arrays(path, data)
    return JointLog(data.seconds(origin), names, position, velocity, f"{path} ({data.topic})")


def _imu_log(path: Path, data: TopicData, origin: int) -> ImuLog:
    gyro, accel, quat = imu_arrays(path, data)
    return ImuLog(data.seconds(origin), gyro, accel, quat, f"{path} ({data.topic})")


def list_bag_topics(path: str | Path) -> Sequence[tuple[str, str, int]]:
    """``(topic, message type, message count)`` of every topic in a bag, sorted by name."""
    reader = _open(Path(path))
    try:
        return [(t, i.msgtype or "", i.msgcount) for t, i in sorted(reader.topics.items())]
    finally:
        reader.close()
