"""F-T logs, joint encoders and IMU from YARP ``yarpdatadumper`` dumps.

Two layouts of the feet are read by :func:`read_yarp_ft` and :func:`read_yarp_robot`:

- **one dump per foot** (as paper A's robot records its JR3 sensors: ``/jr3/ch0:o`` right foot,
  ``/jr3/ch1:o`` left foot): a folder holding the dump folders, each ``data.log`` line carrying
  six values ``F_x F_y F_z τ_x τ_y τ_z`` (nested bottles flattened). A dump is matched to a
  port by the source port its ``info.log`` (or legacy ``Source:`` line) names, else by its
  folder name: ``yarpdatadumper`` names the folder after the port with ``:*?|<>`` turned into
  ``_`` (``/jr3/ch0:o`` → ``jr3/ch0_o``), optionally with a ``_00001``-style suffix.
- **one dump for both feet**: a dump folder or a single ``data.log`` (also the legacy form)
  whose lines carry twelve values, the right wrench then the left.

:func:`read_yarp_robot` also reads, from a folder of per-port dumps:

- **joints**: one or more controlboard ``state:o`` ports (e.g. ``/robot/leftLeg/state:o``,
  ``/robot/rightLeg/state:o``), one value per joint. YARP dumps carry no joint names: give them
  with ``joint_names``, in the order of the ports' values, else they are ``PORT[i]``
  (``/robot/leftLeg/state:o[0]``, …). A controlboard streams positions in **degrees** (revolute
  joints): set ``joint_angle_unit: deg`` in the units YAML. Several ports are joined on the
  first port's clock, cut to the span all cover, the others interpolated linearly
  (:func:`~zmpkit.io.resample.interpolate_stream`, same gap rule as the feet).
- **IMU**: an inertial port, legacy 12-value or multipleanalogsensorsserver bottle
  (:mod:`zmpkit.io.yarp_imu`); gyroscope in deg/s, so set ``imu_angular_velocity_unit: deg/s``.

Stamps become seconds from the earliest first stamp of all the ports read
(:attr:`RobotLog.time_origin_ns`). As in a ROS 2 bag, each stream keeps its own sample times
on that common origin; :func:`~zmpkit.io.resample.resample` puts them on one clock (e.g.
``resample(log, time=log.ft.time)`` for the F-T clock). The two feet are joined by
:func:`~zmpkit.io.resample.merge_feet`. Values are kept in the driver's units; apply
:class:`~zmpkit.io.log_units.LogUnits` (e.g. JR3 moments in dN·m, joints in deg).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.resample import merge_feet
from zmpkit.io.robot_log import RobotLog
from zmpkit.io.yarp_datalog import YarpDump, declared_port, read_yarp_dump
from zmpkit.io.yarp_imu import imu_from_dump
from zmpkit.io.yarp_joints import joint_log_from_dumps, port_list, read_yarp_joints

__all__ = [
    "JR3_LEFT_FOOT_PORT",
    "JR3_RIGHT_FOOT_PORT",
    "find_yarp_dumps",
    "read_yarp_ft",
    "read_yarp_joints",
    "read_yarp_robot",
]

JR3_RIGHT_FOOT_PORT = "/jr3/ch0:o"
"""The right-ankle JR3 channel of paper A's robot (the default right port)."""
JR3_LEFT_FOOT_PORT = "/jr3/ch1:o"
"""The left-ankle JR3 channel of paper A's robot (the default left port)."""

# deepest data.log looked for, in path parts: icub/head/inertials/measures_o/data.log is 5
_MAX_DEPTH = 8
_SUFFIX = re.compile(r"_\d{5}$")


def read_yarp_ft(
    path: str | Path,
    *,
    right_port: str | None = None,
    left_port: str | None = None,
    time_source: str = "header",
    max_gap_s: float | None = None,
) -> RobotLog:
    """Read both feet's raw wrenches from YARP dumps (see the module for the layouts).

    Args:
        path: a folder of per-port dumps, one dump folder, or one ``data.log`` file.
        right_port: the right foot's port (default :data:`JR3_RIGHT_FOOT_PORT`).
        left_port: the left foot's port (default :data:`JR3_LEFT_FOOT_PORT`).
        time_source: "header" (sender stamp) or "receive", see
            :func:`~zmpkit.io.yarp_datalog.read_yarp_dump`.
        max_gap_s: longest gap [s] the left foot is interpolated across.

    Raises:
        InputFileError: no dump for a port (the dumps present are listed), a wrong number of
            values per line, or any error of the ``data.log`` itself (file and line named).
    """
    return read_yarp_robot(
        path,
        right_port=right_port,
        left_port=left_port,
        time_source=time_source,
        max_gap_s=max_gap_s,
    )


def read_yarp_robot(
    path: str | Path,
    *,
    right_port: str | None = None,
    left_port: str | None = None,
    joint_ports: Sequence[str] = (),
    joint_names: Sequence[str] | None = None,
    imu_port: str | None = None,
    imu_sensor: int = 0,
    time_source: str = "header",
    max_gap_s: float | None = None,
) -> RobotLog:
    """Both feet's raw wrenches, and joints and IMU where asked, from YARP dumps.

    Args:
        path: a folder of per-port dumps; for the feet alone also one dump folder or file.
        right_port: the right foot's port (default :data:`JR3_RIGHT_FOOT_PORT`).
        left_port: the left foot's port (default :data:`JR3_LEFT_FOOT_PORT`).
        joint_ports: controlboard ``state:o`` ports, joined in this order; () for none.
        joint_names: one name per joint value of ``joint_ports`` in order; None: ``PORT[i]``.
        imu_port: an inertial port (:mod:`zmpkit.io.yarp_imu`), or None.
        imu_sensor: which sensor of a multipleanalogsensorsserver bottle (0 for the first).
        time_source: "header" (sender stamp) or "receive", see
            :func:`~zmpkit.io.yarp_datalog.read_yarp_dump`.
        max_gap_s: longest gap [s] interpolated across (left foot, further joint ports).

    Returns:
        The log: raw values (module), times [s] from the earliest first stamp of all ports.

    Raises:
        ParameterError: joint names without joint ports, a repeated port or name, or joint or
            IMU ports with a single dump.
        InputFileError: no dump for a port (the dumps present are listed), a wrong number of
            values per line, or any error of a ``data.log`` itself (file and line named).
    """
    path = Path(path)
    joint_ports = port_list(joint_ports)
    if joint_names is not None and not joint_ports:
        raise ParameterError("joint_names needs joint ports (joint_topic) to name")
    if path.is_file() or (path / "data.log").is_file():
        dumps = _single_dump(path, joint_ports, imu_port, time_source)
    else:
        ports = (right_port or JR3_RIGHT_FOOT_PORT, left_port or JR3_LEFT_FOOT_PORT)
        dumps = _port_dumps(path, ports, joint_ports, imu_port, time_source)
    right, left, right_values, left_values, joint_dumps, imu_dump = dumps
    streams = [right, left, *joint_dumps] + ([imu_dump] if imu_dump is not None else [])
    origin = min(float(d.stamp[0]) for d in streams)
    right_t, left_t = right.stamp - origin, left.stamp - origin
    ft = merge_feet(
        right_t, right_values, left_t, left_values, source=str(path), max_gap_s=max_gap_s
    )
    joints = None
    if joint_dumps:
        joints = joint_log_from_dumps(
            path, joint_dumps, joint_ports, joint_names, origin, max_gap_s
        )
    imu = None if imu_dump is None else imu_from_dump(imu_dump, origin, imu_sensor)
    return RobotLog(
        ft=ft, joints=joints, imu=imu, time_origin_ns=round(origin * 1e9), source=str(path)
    )


class _Dumps(NamedTuple):
    """The dumps of a robot log: the feet's (and their wrenches), the joints', the IMU's."""

    right: YarpDump
    left: YarpDump
    right_values: NDArray[np.float64]
    left_values: NDArray[np.float64]
    joints: list[YarpDump]
    imu: YarpDump | None


def _single_dump(
    path: Path, joint_ports: Sequence[str], imu_port: str | None, time_source: str
) -> _Dumps:
    """One dump of both feet's wrenches (12 values a line: the right, then the left)."""
    if joint_ports or imu_port is not None:
        raise ParameterError(
            f"{path} is a single dump; joint and IMU ports need the folder that holds "
            "one dump folder per port"
        )
    dump = read_yarp_dump(path, time_source)
    _require_width(dump, 12, "the right wrench then the left, in a single dump")
    return _Dumps(dump, dump, dump.values[:, :6], dump.values[:, 6:], [], None)


def _port_dumps(
    path: Path,
    feet_ports: tuple[str, str],
    joint_ports: Sequence[str],
    imu_port: str | None,
    time_source: str,
) -> _Dumps:
    """The dumps of the folder ``path``: one per port, the feet's (right, left) first."""
    dumps = find_yarp_dumps(path)
    right = _dump_for(path, dumps, feet_ports[0], time_source)
    left = _dump_for(path, dumps, feet_ports[1], time_source)
    for dump in (right, left):
        _require_width(dump, 6, "F_x F_y F_z τ_x τ_y τ_z")
    joint_dumps = [_dump_for(path, dumps, port, time_source) for port in joint_ports]
    imu_dump = None if imu_port is None else _dump_for(path, dumps, imu_port, time_source)
    return _Dumps(right, left, right.values, left.values, joint_dumps, imu_dump)


def find_yarp_dumps(path: str | Path) -> dict[Path, str]:
    """Every dump folder below ``path`` (``data.log`` inside), with the port it names or "".

    Raises:
        InputFileError: ``path`` is not a folder or holds no dump.
    """
    path = Path(path)
    if not path.is_dir():
        raise InputFileError(path, "not found; expected a folder of yarpdatadumper dumps")
    found = sorted(
        p.parent for p in path.rglob("data.log") if len(p.relative_to(path).parts) <= _MAX_DEPTH
    )
    if not found:
        raise InputFileError(path, "holds no data.log; expected yarpdatadumper dump folders")
    return {folder: declared_port(folder) for folder in found}


def _folder_name(port: str) -> str:
    return re.sub(r"[:*?|<>]", "_", port).strip("/")


def _dump_for(root: Path, dumps: dict[Path, str], port: str, time_source: str) -> YarpDump:
    by_port = [f for f, p in dumps.items() if p == port]
    wanted = _folder_name(port)
    by_name = [
        f
        for f in dumps
        if _SUFFIX.sub("", f.relative_to(root).as_posix()) in (wanted, wanted.split("/")[-1])
    ]
    matches = by_port or by_name
    if len(matches) != 1:
        listed = ", ".join(
            f"{f.relative_to(root).as_posix() or '.'} ({p or 'port unknown'})"
            for f, p in dumps.items()
        )
        what = "no dump" if not matches else f"{len(matches)} dumps"
        raise InputFileError(root, f"{what} of port '{port}' found; dumps present: {listed}")
    return read_yarp_dump(matches[0], time_source)


def _require_width(dump: YarpDump, width: int, layout: str) -> None:
    got = dump.values.shape[1]
    if got != width:
        raise InputFileError(dump.source, f"expected {width} values per line ({layout}), got {got}")
