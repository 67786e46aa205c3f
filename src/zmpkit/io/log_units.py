"""Units and frames of a recorded log, and turning its raw values into zmpkit's.

A units YAML (every key optional)::

    right:                      # the right foot's F-T sensor, a WrenchCalibration plus
      axis_order: [0, 1, 2, 3, 4, 5]
      signs: [1, 1, 1, 1, 1, 1]
      force_unit: N             # N, daN, kgf
      moment_unit: N·m          # N·m, dN·m, daN·m, N·mm
      gain: [1, 1, 1, 1, 1, 1]
      offset: [0, 0, 0, 0, 0, 0]  # [N, N·m], subtracted after the unit scale
      mounting_rpy: [0, 0, 0]   # [rad] rotation of the raw sensor frame in the FEET.yaml one
    left: {...}                 # same keys
    joint_angle_unit: deg       # rad or deg; joint velocities follow (deg/s)
    imu_angular_velocity_unit: rad/s  # rad/s or deg/s

The wrench of each foot goes through :class:`~zmpkit.sensors.WrenchCalibration` (axis order,
signs, units, gain, offset) and is then rotated into the sensor frame that FEET.yaml
describes: ``F ← R F``, ``τ ← R τ`` with ``R = rpy_to_matrix(mounting_rpy)`` (the two frames
share their origin).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.ft_log import FtLog
from zmpkit.io.robot_log import ImuLog, JointLog, RobotLog
from zmpkit.io.yaml_file import read_yaml_mapping, require_vector
from zmpkit.sensors import WrenchCalibration, rpy_to_matrix

__all__ = ["ANGLE_UNIT_SCALE", "FootUnits", "LogUnits", "read_log_units"]

ANGLE_UNIT_SCALE: Mapping[str, float] = {"rad": 1.0, "deg": math.pi / 180.0}
"""Radians per unit of each joint angle unit [rad/unit]."""

_RATE_UNIT_SCALE: Mapping[str, float] = {"rad/s": 1.0, "deg/s": math.pi / 180.0}
_CALIBRATION_KEYS = ("axis_order", "signs", "force_unit", "moment_unit", "gain", "offset")
_FOOT_KEYS = (*_CALIBRATION_KEYS, "mounting_rpy")
_TOP_KEYS = ("right", "left", "joint_angle_unit", "imu_angular_velocity_unit")


@dataclass(frozen=True)
class FootUnits:
    """One foot's raw F-T channels → wrench in the FEET.yaml sensor frame [N, N·m].

    Attributes:
        calibration: axis order, signs, units, gain and offset of the raw channels.
        mounting_rpy: orientation of the raw sensor frame in the FEET.yaml sensor frame
            (roll, pitch, yaw) [rad].
    """

    calibration: WrenchCalibration = field(default_factory=WrenchCalibration)
    mounting_rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def apply(self, raw: NDArray[np.float64]) -> NDArray[np.float64]:
        """Wrench [N, N·m], shape (N, 6), of raw samples (N, 6)."""
        wrench = self.calibration.apply(raw)
        rotation = rpy_to_matrix(self.mounting_rpy)
        return np.hstack([wrench[:, :3] @ rotation.T, wrench[:, 3:] @ rotation.T])


@dataclass(frozen=True)
class LogUnits:
    """Units and frames of a log's raw values; identity by default.

    Attributes:
        right: the right foot's sensor.
        left: the left foot's sensor.
        joint_angle_unit: unit of raw joint angles, "rad" or "deg" (velocities per second).
        imu_angular_velocity_unit: unit of raw IMU angular velocity, "rad/s" or "deg/s".
    """

    right: FootUnits = field(default_factory=FootUnits)
    left: FootUnits = field(default_factory=FootUnits)
    joint_angle_unit: str = "rad"
    imu_angular_velocity_unit: str = "rad/s"

    def __post_init__(self) -> None:
        for name, unit, table in (
            ("joint_angle_unit", self.joint_angle_unit, ANGLE_UNIT_SCALE),
            ("imu_angular_velocity_unit", self.imu_angular_velocity_unit, _RATE_UNIT_SCALE),
        ):
            if unit not in table:
                valid = ", ".join(repr(u) for u in table)
                raise ParameterError(f"unknown {name} {unit!r}; valid: {valid}")

    def apply_ft(self, ft: FtLog) -> FtLog:
        """Both feet's wrenches in [N, N·m] in the FEET.yaml sensor frames."""
        return dataclasses.replace(
            ft,
            right_wrench=self.right.apply(ft.right_wrench),
            left_wrench=self.left.apply(ft.left_wrench),
        )

    def apply_joints(self, joints: JointLog) -> JointLog:
        """Joint angles in [rad] and velocities in [rad/s]."""
        scale = ANGLE_UNIT_SCALE[self.joint_angle_unit]
        velocity = None if joints.velocity is None else joints.velocity * scale
        return dataclasses.replace(joints, position=joints.position * scale, velocity=velocity)

    def apply_imu(self, imu: ImuLog) -> ImuLog:
        """IMU angular velocity in [rad/s]; acceleration and orientation unchanged."""
        scale = _RATE_UNIT_SCALE[self.imu_angular_velocity_unit]
        return dataclasses.replace(imu, angular_velocity=imu.angular_velocity * scale)

    def apply(self, log: RobotLog) -> RobotLog:
        """Every stream of ``log`` in zmpkit's units and frames."""
        return dataclasses.replace(
            log,
            ft=self.apply_ft(log.ft),
            joints=None if log.joints is None else self.apply_joints(log.joints),
            imu=None if log.imu is None else self.apply_imu(log.imu),
        )


def read_log_units(path: str | Path) -> LogUnits:
    """Read a units YAML (see the module) into a :class:`LogUnits`.

    Raises:
        InputFileError: an unknown key (the valid ones listed) or a bad value, naming the field.
    """
    path = Path(path)
    data = read_yaml_mapping(path)
    _check_keys(path, "", data, _TOP_KEYS)
    feet = {name: _foot_units(path, name, data.get(name, {})) for name in ("right", "left")}
    try:
        return LogUnits(
            **feet,
            joint_angle_unit=data.get("joint_angle_unit", "rad"),
            imu_angular_velocity_unit=data.get("imu_angular_velocity_unit", "rad/s"),
        )
    except ParameterError as exc:
        raise InputFileError(path, str(exc)) from None


def _foot_units(path: Path, name: str, entry: Any) -> FootUnits:
    if not isinstance(entry, Mapping):
        raise InputFileError(
            path, f"field '{name}' must be a mapping with keys {', '.join(_FOOT_KEYS)}"
        )
    _check_keys(path, f"{name}.", entry, _FOOT_KEYS)
    rpy = entry.get("mounting_rpy", [0.0, 0.0, 0.0])
    mounting = require_vector(path, f"{name}.mounting_rpy", rpy, 3)
    kwargs = {k: entry[k] for k in _CALIBRATION_KEYS if k in entry}
    try:
        calibration = WrenchCalibration(**kwargs)
    except (ParameterError, TypeError) as exc:
        raise InputFileError(path, f"field '{name}': {exc}") from None
    return FootUnits(calibration, mounting)


def _check_keys(path: Path, prefix: str, data: Mapping[str, Any], valid: tuple[str, ...]) -> None:
    unknown = sorted(str(k) for k in data if k not in valid)
    if unknown:
        raise InputFileError(
            path, f"unknown field '{prefix}{unknown[0]}'; valid: {', '.join(valid)}"
        )
