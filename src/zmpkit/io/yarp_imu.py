"""IMU readings from a YARP inertial port's ``yarpdatadumper`` dump.

Two layouts, told apart by the nesting of the lines
(:attr:`~zmpkit.io.yarp_datalog.YarpDump.layout`): 10 to 12 nested groups are a
multipleanalogsensorsserver bottle, otherwise 12 values are the legacy inertial one.

- **inertial (12 values)**, the legacy ``inertial`` wrapper (``ServerInertial``) and the
  devices written for it (``xsensmtx``, the Gazebo IMU plugin): one flat bottle ::

      roll pitch yaw [deg]   a_x a_y a_z [m/s²]   ω_x ω_y ω_z [deg/s]   m_x m_y m_z

  Source: the ``ServerInertial`` class documentation in YARP ("We will stream bottles with 12
  floats: 0 1 2 = Euler orientation data, 3 4 5 = Calibrated 3-axis (X, Y, Z) acceleration
  data, 6 7 8 = … gyroscope data, 9 10 11 = … magnetometer data",
  ``src/devices/ServerInertial/ServerInertial.h``); the units are those of the
  gazebo-yarp-plugins ``IMUDriver.cpp``, which converts orientation and angular velocity to
  degrees and keeps acceleration in m/s², and which serves the same 12 numbers through the
  multiple-analog-sensors interfaces below.
- **multipleanalogsensorsserver** (``/<prefix>/measures:o``, e.g. iCub's
  ``/icub/head/inertials/measures:o``): a ``SensorStreamingData`` bottle of 10, 11 or 12
  sensor groups, in this order (YARP ``multipleAnalogSensorsSerializations.thrift``; groups 11
  and 12 were appended later): ThreeAxisGyroscopes, ThreeAxisLinearAccelerometers,
  ThreeAxisMagnetometers, OrientationSensors, TemperatureSensors, SixAxisForceTorqueSensors,
  ContactLoadCellArrays, EncoderArrays, SkinPatches, PositionSensors, [LinearVelocitySensors],
  [ThreeAxisAngularAccelerometers]. Each group lists its sensors as ``((x y z) timestamp)``;
  an empty group is ``()``. A line reads e.g. ::

      17 1712345678.12 (((0.1 -0.2 0.3) 1712345678.11)) (((0.0 0.1 9.8) 1712345678.11)) ()
      (((1.0 -2.0 90.0) 1712345678.11)) () () () () () ()

  Units (YARP ``MultipleAnalogSensorsInterfaces.h``): gyroscope [deg/s], accelerometer
  [m/s²], orientation roll, pitch, yaw [deg] with ``R = Rz(yaw) Ry(pitch) Rx(roll)`` the
  rotation of the sensor frame in the lab frame. Sensor ``sensor`` (default 0) of each group
  is read; the per-sensor timestamps are ignored for the line's stamp, as for every port.

The legacy layout's roll, pitch and yaw are read with the orientation sensors' convention:
``ServerInertial`` itself only says "Euler orientation data (X, Y, Z)", but the Gazebo plugin
serves the same 12 numbers through both interfaces. A dump line is one line (wrapped above).

Angular velocity is kept **as the port gives it, in deg/s**: set
``imu_angular_velocity_unit: deg/s`` in the units YAML (:class:`~zmpkit.io.log_units.LogUnits`),
as for paper A's JR3 moments in dN·m. Orientation is turned into a unit quaternion (x, y, z, w)
from the degrees the two layouts define; acceleration is kept in m/s²; the magnetometer is
not read.
"""

from __future__ import annotations

from pathlib import Path
from typing import TypeGuard

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.robot_log import ImuLog
from zmpkit.io.yarp_datalog import Layout, YarpDump, read_yarp_dump

__all__ = ["MAS_GROUPS", "imu_from_dump", "read_yarp_imu"]

MAS_GROUPS = (
    "ThreeAxisGyroscopes",
    "ThreeAxisLinearAccelerometers",
    "ThreeAxisMagnetometers",
    "OrientationSensors",
    "TemperatureSensors",
    "SixAxisForceTorqueSensors",
    "ContactLoadCellArrays",
    "EncoderArrays",
    "SkinPatches",
    "PositionSensors",
    "LinearVelocitySensors",
    "ThreeAxisAngularAccelerometers",
)
"""The sensor groups of a multipleanalogsensorsserver bottle, in order (10 to 12 present)."""

_GYRO, _ACCEL, _ORIENTATION = 0, 1, 3
_INERTIAL_WIDTH = 12


def read_yarp_imu(path: str | Path, time_source: str = "header", sensor: int = 0) -> ImuLog:
    """IMU readings from an inertial port's dump; times are the raw stamps [s] (YARP clock).

    Args:
        path: the dump folder or its ``data.log``.
        time_source: see :func:`~zmpkit.io.yarp_datalog.read_yarp_dump`.
        sensor: which sensor of each multipleanalogsensorsserver group (0 for the first).

    Raises:
        InputFileError: a layout that is neither of the module's, or any error of the dump
            itself (file and line named).
    """
    return imu_from_dump(read_yarp_dump(path, time_source), 0.0, sensor)


def imu_from_dump(dump: YarpDump, origin: float, sensor: int = 0) -> ImuLog:
    """The :class:`ImuLog` of a dump, times ``stamp − origin`` [s]; see the module for units.

    Raises:
        ParameterError: ``sensor`` is not a non-negative integer.
        InputFileError: the dump's layout is neither of the module's, or lacks the sensor.
    """
    if isinstance(sensor, bool) or not isinstance(sensor, int) or sensor < 0:
        raise ParameterError(f"sensor must be an integer >= 0, got {sensor!r}")
    layout = dump.layout
    if 10 <= len(layout) <= len(MAS_GROUPS) and all(isinstance(g, tuple) for g in layout):
        gyro = dump.values[:, _mas_columns(dump, layout, _GYRO, sensor)]
        accel = dump.values[:, _mas_columns(dump, layout, _ACCEL, sensor)]
        rpy = None
        if layout[_ORIENTATION]:
            rpy = dump.values[:, _mas_columns(dump, layout, _ORIENTATION, sensor)]
    elif dump.values.shape[1] == _INERTIAL_WIDTH:
        columns = dump.values
        gyro, accel, rpy = columns[:, 6:9], columns[:, 3:6], columns[:, 0:3]
    else:
        raise InputFileError(
            dump.source,
            f"expected an IMU port: {_INERTIAL_WIDTH} values (roll pitch yaw [deg], a_xyz "
            "[m/s²], ω_xyz [deg/s], m_xyz) or a multipleanalogsensorsserver bottle of 10 to "
            f"{len(MAS_GROUPS)} sensor groups; got {_describe(dump)}",
            row=dump.first_line,
        )
    quat = None if rpy is None else _quaternions(rpy)
    return ImuLog(dump.stamp - origin, gyro, accel, quat, dump.source)


def _mas_columns(dump: YarpDump, layout: Layout, group: int, sensor: int) -> list[int]:
    """Value columns of ``(x y z)`` of sensor ``sensor`` in ``group`` of a MAS bottle."""
    name = MAS_GROUPS[group]
    measurements = layout[group]
    assert isinstance(measurements, tuple)
    if len(measurements) <= sensor:
        raise InputFileError(
            dump.source,
            f"{name} has {len(measurements)} sensor(s); expected sensor {sensor} "
            f"(counting from 0) as '((x y z) timestamp)'",
            row=dump.first_line,
        )
    measurement = measurements[sensor]
    if not _is_xyz_measurement(measurement):
        raise InputFileError(
            dump.source,
            f"{name} sensor {sensor}: expected '((x y z) timestamp)', got "
            f"{_describe_item(measurement)}",
            row=dump.first_line,
        )
    return list(measurement[0])


def _is_xyz_measurement(item: int | Layout) -> TypeGuard[tuple[tuple[int, int, int], int]]:
    """Whether ``item`` is the layout ``((x y z) timestamp)``: three value columns, one stamp."""
    return (
        isinstance(item, tuple)
        and len(item) == 2
        and isinstance(item[0], tuple)
        and len(item[0]) == 3
        and all(isinstance(k, int) for k in item[0])
        and isinstance(item[1], int)
    )


def _describe(dump: YarpDump) -> str:
    width = dump.values.shape[1]
    if all(isinstance(k, int) for k in dump.layout):
        return f"{width} values per line"
    return f"{width} values in {len(dump.layout)} nested items per line"


def _describe_item(item: object) -> str:
    if isinstance(item, int):
        return "a single number"
    assert isinstance(item, tuple)
    return f"a list of {len(item)} items"


def _quaternions(rpy_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit quaternions (x, y, z, w) of ``R = Rz(yaw) Ry(pitch) Rx(roll)``, angles in deg."""
    return Rotation.from_euler("xyz", rpy_deg, degrees=True).as_quat()
