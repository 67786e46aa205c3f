"""Deserialised ROS 2 messages of one topic → checked numpy arrays.

Used by :mod:`zmpkit.io.rosbag`; every error names the bag, the topic and the message
(1-based, in the order the bag stores them).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError

__all__ = ["TopicData", "imu_arrays", "joint_arrays", "wrench_array"]

_WRENCH_FIELDS = tuple(f"wrench.{p}.{a}" for p in ("force", "torque") for a in "xyz")
_GYRO_FIELDS = tuple(f"angular_velocity.{a}" for a in "xyz")
_ACCEL_FIELDS = tuple(f"linear_acceleration.{a}" for a in "xyz")
_QUAT_FIELDS = tuple(f"orientation.{a}" for a in "xyzw")


@dataclass
class TopicData:
    """The messages of one topic and their stamps, gathered while the bag is read.

    Attributes:
        topic: the topic name.
        stamps: one stamp per message [ns].
        messages: the deserialised messages.
    """

    topic: str
    stamps: list[int] = field(default_factory=list)
    messages: list[Any] = field(default_factory=list)

    def append(self, stamp_ns: int, message: Any) -> None:
        """Add one message with its stamp [ns]."""
        self.stamps.append(stamp_ns)
        self.messages.append(message)

    @property
    def stamps_ns(self) -> NDArray[np.int64]:
        """The stamps [ns], shape (N,)."""
        return np.asarray(self.stamps, dtype=np.int64)

    def seconds(self, origin_ns: int) -> NDArray[np.float64]:
        """Stamps relative to ``origin_ns`` [s], subtracted in integer ns first."""
        return (self.stamps_ns - np.int64(origin_ns)) / 1e9

    def check_stamps(self, path: Path, kind: str) -> None:
        """Raise unless the stamps are strictly increasing; ``kind`` names them."""
        stamps = self.stamps_ns
        bad = np.flatnonzero(np.diff(stamps) <= 0)
        if bad.size:
            k = int(bad[0]) + 1
            hint = "; try time_source='receive'" if kind == "header" else ""
            raise InputFileError(
                path,
                f"topic '{self.topic}': {kind} stamps must be strictly increasing, but message "
                f"{k + 1} ({_ns(stamps[k])} s) follows message {k} ({_ns(stamps[k - 1])} s){hint}",
            )


def _ns(stamp_ns: int) -> str:
    """A stamp [ns] written in seconds with all nine decimals, exactly."""
    return f"{int(stamp_ns) // 1_000_000_000}.{int(stamp_ns) % 1_000_000_000:09d}"


def _check_finite(
    path: Path, topic: str, values: NDArray[np.float64], names: tuple[str, ...]
) -> NDArray[np.float64]:
    bad = np.argwhere(~np.isfinite(values))
    if bad.size:
        row, col = (int(i) for i in bad[0])
        raise InputFileError(
            path,
            f"topic '{topic}', message {row + 1}: {names[col]} is {values[row, col]}; "
            "expected a finite number",
        )
    return values


def wrench_array(path: Path, data: TopicData) -> NDArray[np.float64]:
    """``(F_x, F_y, F_z, τ_x, τ_y, τ_z)`` [N, N·m] of WrenchStamped messages, (N, 6)."""
    rows = [
        (f.x, f.y, f.z, t.x, t.y, t.z)
        for f, t in ((m.wrench.force, m.wrench.torque) for m in data.messages)
    ]
    return _check_finite(path, data.topic, np.array(rows, dtype=np.float64), _WRENCH_FIELDS)


def joint_arrays(
    path: Path, data: TopicData
) -> tuple[tuple[str, ...], NDArray[np.float64], NDArray[np.float64] | None]:
    """``(names, position (N, J), velocity (N, J) or None)`` of JointState messages.

    The joint order is that of the first message; later messages may list the same joints
    in another order. Velocity is None when every message leaves it empty.
    """
    names = tuple(str(n) for n in data.messages[0].name)
    if not names or len(set(names)) != len(names):
        raise InputFileError(
            path, f"topic '{data.topic}', message 1: expected distinct joint names, got {names}"
        )
    positions, velocities = [], []
    for k, msg in enumerate(data.messages, start=1):
        order = _joint_order(path, data.topic, k, names, msg.name)
        positions.append(_field(path, data.topic, k, "position", msg.position, len(names))[order])
        if len(msg.velocity):
            velocities.append(
                _field(path, data.topic, k, "velocity", msg.velocity, len(names))[order]
            )
    if velocities and len(velocities) != len(positions):
        raise InputFileError(
            path,
            f"topic '{data.topic}': {len(velocities)} of {len(positions)} messages have "
            "velocities; expected all or none",
        )
    fields = tuple(f"position[{n}]" for n in names)
    position = _check_finite(path, data.topic, np.array(positions), fields)
    velocity = None
    if velocities:
        fields = tuple(f"velocity[{n}]" for n in names)
        velocity = _check_finite(path, data.topic, np.array(velocities), fields)
    return names, position, velocity


def _joint_order(
    path: Path, topic: str, k: int, names: tuple[str, ...], got: list[str]
) -> NDArray[np.intp]:
    index = {str(n): i for i, n in enumerate(got)}
    missing = [n for n in names if n not in index]
    if missing or len(index) != len(names):
        raise InputFileError(
            path,
            f"topic '{topic}', message {k}: joints {sorted(index)} differ from those of "
            f"message 1 {sorted(names)}",
        )
    return np.array([index[n] for n in names], dtype=np.intp)


def _field(path: Path, topic: str, k: int, name: str, values: Any, n: int) -> NDArray[np.float64]:
    arr = np.asarray(values, dtype=np.float64)
    if arr.shape != (n,):
        raise InputFileError(
            path, f"topic '{topic}', message {k}: {arr.size} {name} values for {n} joint names"
        )
    return arr


def imu_arrays(
    path: Path, data: TopicData
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None]:
    """Return the arrays of Imu messages.

    ``(angular velocity (N, 3) [rad/s], linear acceleration (N, 3) [m/s²], quaternion
    (N, 4) (x, y, z, w) or None)`` of Imu messages.

    Orientation is None when every message marks it absent (``orientation_covariance[0] ==
    -1``, the ROS convention).
    """
    msgs = data.messages
    gyro = np.array(
        [(m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z) for m in msgs]
    )
    accel = np.array(
        [(m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z) for m in msgs]
    )
    absent = np.array([m.orientation_covariance[0] == -1.0 for m in msgs])
    quat = None
    if absent.any() and not absent.all():
        raise InputFileError(
            path,
            f"topic '{data.topic}': {int(absent.sum())} of {absent.size} messages mark the "
            "orientation absent (orientation_covariance[0] = -1); expected all or none",
        )
    if not absent.any():
        quat = np.array(
            [(m.orientation.x, m.orientation.y, m.orientation.z, m.orientation.w) for m in msgs]
        )
        _check_finite(path, data.topic, quat, _QUAT_FIELDS)
    _check_finite(path, data.topic, gyro, _GYRO_FIELDS)
    _check_finite(path, data.topic, accel, _ACCEL_FIELDS)
    return gyro, accel, quat
