"""One entry for every kind of recorded log: CSV, Parquet, ROS 2 bag, YARP dumps.

:func:`read_ft_source` looks at what the path is and calls the matching reader:

========================  ==========================================================
path                      read as
========================  ==========================================================
folder with metadata.yaml ROS 2 bag (:func:`~zmpkit.io.rosbag.read_ros2_bag`)
``.db3`` / ``.mcap`` file ROS 2 bag storage file (also found by its magic bytes)
folder with ``data.log``  YARP dumps (:func:`~zmpkit.io.yarp.read_yarp_robot`), also below it
``*.log`` file            a single YARP ``data.log`` (legacy form included)
``.parquet`` / ``.pq``    Parquet (:func:`~zmpkit.io.ft_parquet.read_ft_log_parquet`)
any other file            CSV (:func:`~zmpkit.io.ft_log.read_ft_log_csv`)
========================  ==========================================================

Then the units and frames (:class:`~zmpkit.io.log_units.LogUnits`) are applied.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.ft_log import FtLog, check_plausible, read_column_map, read_ft_log_csv
from zmpkit.io.ft_parquet import read_ft_log_parquet
from zmpkit.io.log_units import LogUnits, read_log_units
from zmpkit.io.robot_log import RobotLog
from zmpkit.io.rosbag import WRENCH_STAMPED_TYPE, list_bag_topics, read_ros2_bag
from zmpkit.io.yarp import read_yarp_robot

__all__ = ["SOURCE_KINDS", "detect_source_kind", "read_ft_source", "read_robot_source"]

SOURCE_KINDS = ("csv", "parquet", "ros2", "yarp")
_MAGIC = {b"PAR1": "parquet", b"SQLite format 3\x00": "ros2", b"\x89MCAP": "ros2"}
_SUFFIX = {".parquet": "parquet", ".pq": "parquet", ".db3": "ros2", ".mcap": "ros2", ".log": "yarp"}


def detect_source_kind(path: str | Path) -> str:
    """Which of :data:`SOURCE_KINDS` ``path`` is (see the module's table).

    Raises:
        InputFileError: the path does not exist, or is a folder of neither kind.
    """
    path = Path(path)
    if path.is_dir():
        if (path / "metadata.yaml").is_file():
            return "ros2"
        if next(path.rglob("data.log"), None) is not None:
            return "yarp"
        raise InputFileError(
            path,
            "is a folder but neither a ROS 2 bag (no metadata.yaml) nor YARP dumps (no data.log)",
        )
    if not path.is_file():
        raise InputFileError(path, "file not found")
    try:
        with path.open("rb") as f:
            head = f.read(16)
    except OSError as exc:
        raise InputFileError(path, f"cannot be read ({exc})") from None
    for magic, kind in _MAGIC.items():
        if head.startswith(magic):
            return kind
    return _SUFFIX.get(path.suffix.lower(), "csv")


def read_robot_source(
    path: str | Path,
    *,
    right_topic: str | None = None,
    left_topic: str | None = None,
    joint_topic: str | Sequence[str] | None = None,
    imu_topic: str | None = None,
    joint_names: Sequence[str] | None = None,
    column_map: Mapping[str, str] | str | Path | None = None,
    units: LogUnits | str | Path | None = None,
    time_source: str = "header",
    max_gap_s: float | None = None,
) -> RobotLog:
    """Read any supported log into a :class:`~zmpkit.io.robot_log.RobotLog`, units applied.

    Each stream keeps its own times, on one origin: :func:`~zmpkit.io.resample.resample`
    puts them on one clock.

    Args:
        path: CSV, Parquet, ROS 2 bag (folder, ``.db3``, ``.mcap``) or YARP dumps.
        right_topic: ROS 2 topic or YARP port of the right foot's wrench.
        left_topic: ROS 2 topic or YARP port of the left foot's wrench.
        joint_topic: ROS 2 JointState topic, or YARP controlboard ``state:o`` port(s) — a
            sequence of ports for several limbs (:func:`~zmpkit.io.yarp.read_yarp_robot`).
        imu_topic: ROS 2 Imu topic, or YARP inertial port (:mod:`zmpkit.io.yarp_imu`).
        joint_names: YARP only (a dump has none): one name per joint value of the
            ``joint_topic`` ports in order; None: ``PORT[i]``. Bags name their joints.
        column_map: ``{canonical: column}`` or a column-map YAML (CSV and Parquet only).
        units: units and frames of the raw values, or a units YAML; None: already SI (YARP
            streams deg and deg/s: say so).
        time_source: "header" (sensor/sender stamps, default) or "receive" (bags and YARP).
        max_gap_s: longest gap [s] interpolated across when streams are joined on one clock.

    Raises:
        InputFileError: anything wrong with the file, naming file and line/topic/column, or
            a force or moment beyond the plausible limits of :func:`~zmpkit.io.check_plausible`.
        ParameterError: an option that does not apply to this kind of source.
    """
    path = Path(path)
    kind = detect_source_kind(path)
    _check_options(kind, right_topic, left_topic, joint_topic, imu_topic, column_map, joint_names)
    if kind in ("csv", "parquet"):
        columns = read_column_map(column_map) if isinstance(column_map, str | Path) else column_map
        reader = read_ft_log_csv if kind == "csv" else read_ft_log_parquet
        log = RobotLog(ft=reader(path, columns), source=str(path))
    elif kind == "yarp":
        joint_ports = () if joint_topic is None else joint_topic
        log = read_yarp_robot(
            path, right_port=right_topic, left_port=left_topic, joint_ports=joint_ports,
            joint_names=joint_names, imu_port=imu_topic, time_source=time_source,
            max_gap_s=max_gap_s,
        )  # fmt: skip
    else:
        log = _read_bag(
            path, right_topic, left_topic, joint_topic, imu_topic, time_source, max_gap_s
        )
    if units is not None:
        log = (units if isinstance(units, LogUnits) else read_log_units(units)).apply(log)
    check_plausible(log.ft)
    return log


def read_ft_source(
    path: str | Path,
    *,
    right_topic: str | None = None,
    left_topic: str | None = None,
    column_map: Mapping[str, str] | str | Path | None = None,
    units: LogUnits | str | Path | None = None,
    time_source: str = "header",
    max_gap_s: float | None = None,
) -> FtLog:
    """Both feet's wrenches [N, N·m] from any supported log; see :func:`read_robot_source`.

    Times are as the file gives them for CSV/Parquet [s], and from the earliest first stamp
    for bags and YARP dumps [s].
    """
    return read_robot_source(
        path,
        right_topic=right_topic,
        left_topic=left_topic,
        column_map=column_map,
        units=units,
        time_source=time_source,
        max_gap_s=max_gap_s,
    ).ft


def _check_options(
    kind: str,
    right_topic: str | None,
    left_topic: str | None,
    joint_topic: str | Sequence[str] | None,
    imu_topic: str | None,
    column_map: object,
    joint_names: Sequence[str] | None,
) -> None:
    """Raise ParameterError for an option that does not apply to a ``kind`` source."""
    topics = {"right_topic": right_topic, "left_topic": left_topic}
    extra = {"joint_topic": joint_topic, "imu_topic": imu_topic}
    if kind in ("csv", "parquet"):
        given = [k for k, v in {**topics, **extra}.items() if v is not None]
        if given:
            raise ParameterError(
                f"{given[0]} applies to ROS 2 bags and YARP dumps, not to a {kind} file"
            )
    elif column_map is not None:
        raise ParameterError(f"column_map applies to CSV and Parquet files, not to {kind} logs")
    if kind == "ros2" and joint_topic is not None and not isinstance(joint_topic, str):
        raise ParameterError(
            "a ROS 2 bag takes one JointState topic as joint_topic; several ports are "
            "for YARP dumps"
        )
    if joint_names is not None and kind != "yarp":
        raise ParameterError(
            f"joint_names applies to YARP dumps, not to {kind} logs "
            "(a ROS 2 bag's JointState messages name their joints)"
        )


def _read_bag(
    path: Path,
    right_topic: str | None,
    left_topic: str | None,
    joint_topic: str | Sequence[str] | None,
    imu_topic: str | None,
    time_source: str,
    max_gap_s: float | None,
) -> RobotLog:
    """The robot log of a ROS 2 bag (its options checked: one joint topic at most)."""
    assert joint_topic is None or isinstance(joint_topic, str)
    if right_topic is None or left_topic is None:
        wrenches = [t for t, kind, _ in list_bag_topics(path) if kind == WRENCH_STAMPED_TYPE]
        raise ParameterError(
            f"{path}: a ROS 2 bag needs right_topic and left_topic (--right-topic, "
            f"--left-topic); its {WRENCH_STAMPED_TYPE} topics: {', '.join(wrenches) or 'none'}"
        )
    return read_ros2_bag(
        path,
        right_topic=right_topic,
        left_topic=left_topic,
        joint_topic=joint_topic,
        imu_topic=imu_topic,
        time_source=time_source,
        max_gap_s=max_gap_s,
    )
