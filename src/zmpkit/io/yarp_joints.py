"""Joint encoders from YARP controlboard ``state:o`` dumps (see :mod:`zmpkit.io.yarp`).

A controlboard's ``state:o`` port streams one position per joint, in degrees for revolute
joints (YARP's ``IEncoders`` convention; e.g. ``/robot/leftLeg/state:o``). A dump has no joint
names; the values are kept in the port's unit, to be converted by
:class:`~zmpkit.io.log_units.LogUnits` (``joint_angle_unit: deg``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.resample import interpolate_stream
from zmpkit.io.robot_log import JointLog
from zmpkit.io.yarp_datalog import YarpDump, read_yarp_dump

__all__ = ["joint_log_from_dumps", "port_list", "read_yarp_joints"]


def read_yarp_joints(
    path: str | Path, names: tuple[str, ...] | None = None, time_source: str = "header"
) -> JointLog:
    """Joint positions from an encoder port's dump (e.g. ``/robot/leftLeg/state:o``).

    Times are the raw stamps [s] (YARP clock); angles are kept in the port's unit (paper A's robot's
    encoders report degrees: convert with :class:`~zmpkit.io.log_units.LogUnits`).

    Args:
        path: the dump folder or its ``data.log``.
        names: joint names, one per value; default ``q0, q1, …``.
        time_source: see :func:`~zmpkit.io.yarp_datalog.read_yarp_dump`.
    """
    dump = read_yarp_dump(path, time_source)
    width = dump.values.shape[1]
    names = names or tuple(f"q{i}" for i in range(width))
    if len(names) != width:
        raise InputFileError(
            dump.source, f"{width} values per line, but {len(names)} joint names were given"
        )
    return JointLog(dump.stamp, tuple(names), dump.values, None, dump.source)


def port_list(ports: Sequence[str] | str) -> tuple[str, ...]:
    """``ports`` as a tuple (one port may be given as a string).

    Raises:
        ParameterError: a port given twice.
    """
    ports = (ports,) if isinstance(ports, str) else tuple(ports)
    repeated = sorted({p for p in ports if ports.count(p) > 1})
    if repeated:
        raise ParameterError(f"joint port '{repeated[0]}' is given twice")
    return ports


def joint_log_from_dumps(
    root: Path,
    dumps: list[YarpDump],
    ports: tuple[str, ...],
    names: Sequence[str] | None,
    origin: float,
    max_gap_s: float | None,
) -> JointLog:
    """Joint positions [port unit] of every port, on the first port's clock.

    Times are ``stamp − origin`` [s]: the other ports are interpolated onto the first
    port's clock over the span all cover.

    Raises:
        InputFileError: names not one per value, or ports that do not overlap in time.
        ParameterError: a name given twice.
    """
    widths = [d.values.shape[1] for d in dumps]
    if names is None:
        names = [f"{port}[{i}]" for port, w in zip(ports, widths, strict=True) for i in range(w)]
    names = tuple(names)
    if len(names) != sum(widths):
        carried = ", ".join(f"{d.source}: {w}" for d, w in zip(dumps, widths, strict=True))
        raise InputFileError(
            root,
            f"{len(names)} joint names were given, but the joint ports carry {sum(widths)} "
            f"values per line ({carried}); expected one name per value",
        )
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ParameterError(f"joint name '{repeated[0]}' is given twice")
    base = dumps[0]
    time = base.stamp - origin
    if all(np.array_equal(d.stamp, base.stamp) for d in dumps):
        position = np.hstack([d.values for d in dumps])
    else:
        start = max(float(d.stamp[0]) for d in dumps) - origin
        end = min(float(d.stamp[-1]) for d in dumps) - origin
        if start > end:
            covers = "; ".join(
                f"{p} covers t = {d.stamp[0] - origin:g} … {d.stamp[-1] - origin:g} s"
                for p, d in zip(ports, dumps, strict=True)
            )
            raise InputFileError(root, f"the joint ports do not overlap in time: {covers}")
        time = time[(time >= start) & (time <= end)]
        position = np.hstack(
            [
                interpolate_stream(d.stamp - origin, d.values, time, p, d.source, max_gap_s)
                for p, d in zip(ports, dumps, strict=True)
            ]
        )
    return JointLog(time, names, position, None, f"{root} ({', '.join(ports)})")
