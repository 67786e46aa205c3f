"""F-T logs (and joint encoders) from YARP ``yarpdatadumper`` dumps.

Two layouts are read by :func:`read_yarp_ft`:

- **one dump per foot** (as TEO records its JR3 sensors: ``/jr3/ch0:o`` right foot,
  ``/jr3/ch1:o`` left foot): a folder holding the dump folders, each ``data.log`` line carrying
  six values ``F_x F_y F_z τ_x τ_y τ_z`` (nested bottles flattened). A dump is matched to a
  port by the source port its ``info.log`` (or legacy ``Source:`` line) names, else by its
  folder name: ``yarpdatadumper`` names the folder after the port with ``:*?|<>`` turned into
  ``_`` (``/jr3/ch0:o`` → ``jr3/ch0_o``), optionally with a ``_00001``-style suffix.
- **one dump for both feet**: a dump folder or a single ``data.log`` (also the legacy form)
  whose lines carry twelve values, the right wrench then the left.

Stamps become seconds from the earliest first stamp (:attr:`RobotLog.time_origin_ns`); the two
feet are joined by :func:`~zmpkit.io.resample.merge_feet`. Values are kept in the driver's
units; apply :class:`~zmpkit.io.log_units.LogUnits` (e.g. JR3 moments in dN·m).
"""

from __future__ import annotations

import re
from pathlib import Path

from zmpkit.errors import InputFileError
from zmpkit.io.resample import merge_feet
from zmpkit.io.robot_log import JointLog, RobotLog
from zmpkit.io.yarp_datalog import YarpDump, declared_port, read_yarp_dump

__all__ = [
    "TEO_LEFT_FOOT_PORT",
    "TEO_RIGHT_FOOT_PORT",
    "find_yarp_dumps",
    "read_yarp_ft",
    "read_yarp_joints",
]

TEO_RIGHT_FOOT_PORT = "/jr3/ch0:o"
"""TEO's right-ankle JR3 channel."""
TEO_LEFT_FOOT_PORT = "/jr3/ch1:o"
"""TEO's left-ankle JR3 channel."""

_MAX_DEPTH = 4
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
        right_port: the right foot's port (default :data:`TEO_RIGHT_FOOT_PORT`).
        left_port: the left foot's port (default :data:`TEO_LEFT_FOOT_PORT`).
        time_source: "header" (sender stamp) or "receive", see
            :func:`~zmpkit.io.yarp_datalog.read_yarp_dump`.
        max_gap_s: longest gap [s] the left foot is interpolated across.

    Raises:
        InputFileError: no dump for a port (the dumps present are listed), a wrong number of
            values per line, or any error of the ``data.log`` itself (file and line named).
    """
    path = Path(path)
    if path.is_file() or (path / "data.log").is_file():
        dump = read_yarp_dump(path, time_source)
        _require_width(dump, 12, "the right wrench then the left, in a single dump")
        right, left = dump, dump
        right_values, left_values = dump.values[:, :6], dump.values[:, 6:]
    else:
        dumps = find_yarp_dumps(path)
        right = _dump_for(path, dumps, right_port or TEO_RIGHT_FOOT_PORT, time_source)
        left = _dump_for(path, dumps, left_port or TEO_LEFT_FOOT_PORT, time_source)
        for dump in (right, left):
            _require_width(dump, 6, "F_x F_y F_z τ_x τ_y τ_z")
        right_values, left_values = right.values, left.values
    origin = min(right.stamp[0], left.stamp[0])
    ft = merge_feet(
        right.stamp - origin,
        right_values,
        left.stamp - origin,
        left_values,
        source=str(path),
        max_gap_s=max_gap_s,
    )
    return RobotLog(ft=ft, time_origin_ns=round(origin * 1e9), source=str(path))


def read_yarp_joints(
    path: str | Path, names: tuple[str, ...] | None = None, time_source: str = "header"
) -> JointLog:
    """Joint positions from an encoder port's dump (e.g. ``/teo/leftLeg/state:o``).

    Times are the raw stamps [s] (YARP clock); angles are kept in the port's unit (TEO's
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
