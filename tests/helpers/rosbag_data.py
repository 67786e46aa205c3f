"""ROS 2 messages and bags for tests, written with rosbags' Writer and typestore."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from rosbags.rosbag2 import Writer
from rosbags.rosbag2.enums import StoragePlugin
from rosbags.typesys import Stores, get_typestore

TS = get_typestore(Stores.LATEST)
WRENCH = "geometry_msgs/msg/WrenchStamped"
JOINTS = "sensor_msgs/msg/JointState"
IMU = "sensor_msgs/msg/Imu"
T0_NS = 1_712_345_678_123_456_789
PLUGINS = [StoragePlugin.SQLITE3, StoragePlugin.MCAP]


def _header(stamp_ns: int) -> object:
    stamp = TS.types["builtin_interfaces/msg/Time"](
        sec=stamp_ns // 1_000_000_000, nanosec=stamp_ns % 1_000_000_000
    )
    return TS.types["std_msgs/msg/Header"](stamp=stamp, frame_id="sensor")


def _vec(x: float, y: float, z: float) -> object:
    return TS.types["geometry_msgs/msg/Vector3"](x=x, y=y, z=z)


def wrench_msg(stamp_ns: int, w: np.ndarray) -> object:
    wrench = TS.types["geometry_msgs/msg/Wrench"](force=_vec(*w[:3]), torque=_vec(*w[3:]))
    return TS.types[WRENCH](header=_header(stamp_ns), wrench=wrench)


def joint_msg(stamp_ns: int, names: list[str], pos: np.ndarray, vel: np.ndarray) -> object:
    return TS.types[JOINTS](
        header=_header(stamp_ns), name=names, position=pos, velocity=vel, effort=np.zeros(0)
    )


def imu_msg(stamp_ns: int, gyro: np.ndarray, acc: np.ndarray, quat: np.ndarray) -> object:
    q = TS.types["geometry_msgs/msg/Quaternion"](x=quat[0], y=quat[1], z=quat[2], w=quat[3])
    cov = np.zeros(9)
    return TS.types[IMU](
        header=_header(stamp_ns),
        orientation=q,
        orientation_covariance=cov,
        angular_velocity=_vec(*gyro),
        angular_velocity_covariance=cov,
        linear_acceleration=_vec(*acc),
        linear_acceleration_covariance=cov,
    )


def write_bag(
    path: Path, topics: dict[str, tuple[str, list[tuple[int, object]]]], plugin: StoragePlugin
) -> Path:
    """``topics``: ``{topic: (msgtype, [(receive_ns, message), ...])}``."""
    with Writer(path, version=9, storage_plugin=plugin) as writer:
        for topic, (msgtype, messages) in topics.items():
            connection = writer.add_connection(topic, msgtype, typestore=TS)
            for receive_ns, msg in messages:
                writer.write(connection, receive_ns, TS.serialize_cdr(msg, msgtype))
    return path
