"""What a real robot recorded: F-T wrenches, joint states and IMU, each on its own clock.

A :class:`RobotLog` holds an :class:`~zmpkit.io.ft_log.FtLog` (both feet on one clock) and,
where the source has them, a :class:`JointLog` and an :class:`ImuLog`. Each stream keeps the
sample times it was recorded with; :func:`zmpkit.io.resample.resample` puts them onto one
clock. Times of streams read from the same source share one origin
(:attr:`RobotLog.time_origin_ns`), so they can be compared directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.io.ft_log import FtLog

__all__ = ["ImuLog", "JointLog", "RobotLog", "check_stream"]


def check_stream(name: str, time: NDArray[np.float64], **signals: NDArray | None) -> None:
    """Check one stream: time finite and strictly increasing, signals finite with N rows.

    Raises:
        ParameterError: naming the stream and the signal that is wrong.
    """
    if time.ndim != 1 or time.size == 0:
        raise ParameterError(f"{name}.time must be a non-empty 1-D array, got shape {time.shape}")
    if not np.all(np.isfinite(time)) or np.any(np.diff(time) <= 0.0):
        raise ParameterError(f"{name}.time must be finite and strictly increasing [s]")
    for signal, values in signals.items():
        if values is None:
            continue
        if values.shape[0] != time.shape[0]:
            raise ParameterError(
                f"{name}.{signal} has {values.shape[0]} rows, {name}.time has {time.shape[0]}"
            )
        if not np.all(np.isfinite(values)):
            raise ParameterError(f"{name}.{signal} must be finite everywhere")


@dataclass(frozen=True)
class JointLog:
    """Joint encoder readings over time.

    Attributes:
        time: sample times, strictly increasing [s], shape (N,).
        names: joint names, J of them, in column order.
        position: joint angles [rad] (or [m] for prismatic joints), shape (N, J).
        velocity: joint velocities [rad/s], shape (N, J), or None where the source has none.
        source: where the stream came from (file and topic or port).
    """

    time: NDArray[np.float64]
    names: tuple[str, ...]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64] | None = None
    source: str = ""

    def __post_init__(self) -> None:
        check_stream("joints", self.time, position=self.position, velocity=self.velocity)
        if self.position.ndim != 2 or self.position.shape[1] != len(self.names):
            raise ParameterError(
                f"joints.position must have shape (N, {len(self.names)}) for the "
                f"{len(self.names)} names, got {self.position.shape}"
            )
        if self.velocity is not None and self.velocity.shape != self.position.shape:
            raise ParameterError(
                f"joints.velocity must have the shape of position {self.position.shape}, "
                f"got {self.velocity.shape}"
            )

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return int(self.time.shape[0])


@dataclass(frozen=True)
class ImuLog:
    """IMU readings over time, in the IMU's own frame.

    Attributes:
        time: sample times, strictly increasing [s], shape (N,).
        angular_velocity: angular velocity of the IMU in the IMU frame [rad/s], shape (N, 3).
        linear_acceleration: specific force (gravity included) in the IMU frame [m/s²], (N, 3).
        orientation_xyzw: orientation of the IMU frame in its reference frame as a unit
            quaternion, scalar last (x, y, z, w) as ROS and SciPy write it [-], shape (N, 4);
            None where the source gives no orientation.
        source: where the stream came from (file and topic or port).
    """

    time: NDArray[np.float64]
    angular_velocity: NDArray[np.float64]
    linear_acceleration: NDArray[np.float64]
    orientation_xyzw: NDArray[np.float64] | None = None
    source: str = ""

    def __post_init__(self) -> None:
        check_stream(
            "imu",
            self.time,
            angular_velocity=self.angular_velocity,
            linear_acceleration=self.linear_acceleration,
            orientation_xyzw=self.orientation_xyzw,
        )
        shapes = {"angular_velocity": 3, "linear_acceleration": 3, "orientation_xyzw": 4}
        for name, width in shapes.items():
            values = getattr(self, name)
            if values is not None and (values.ndim != 2 or values.shape[1] != width):
                raise ParameterError(f"imu.{name} must have shape (N, {width}), got {values.shape}")

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return int(self.time.shape[0])


@dataclass(frozen=True)
class RobotLog:
    """Everything read from one recording; each stream on its own clock.

    Attributes:
        ft: both feet's wrenches in each sensor's frame [N, N·m].
        joints: joint states, or None where the source has none.
        imu: IMU readings, or None where the source has none.
        time_origin_ns: absolute time of t = 0 in every stream [ns] on the source's clock
            (Unix time for ROS 2 header stamps and YARP stamps); 0 where the source's times
            are already relative (CSV, Parquet).
        source: the file or folder read.
    """

    ft: FtLog
    joints: JointLog | None = None
    imu: ImuLog | None = None
    time_origin_ns: int = 0
    source: str = ""

    def streams(self) -> dict[str, NDArray[np.float64]]:
        """The sample times of each stream present, by name ("ft", "joints", "imu") [s]."""
        present = {"ft": self.ft, "joints": self.joints, "imu": self.imu}
        return {name: s.time for name, s in present.items() if s is not None}
