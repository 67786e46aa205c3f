"""The ``zmpkit zmp`` pipeline: an F-T log in, the measured ZMP out (CSV + figure).

:func:`run_zmp_log` reads the log and computes its ZMP (nothing is written);
:func:`~zmpkit.pipelines.zmp_log_files.write_zmp_log` writes ``zmp.csv``, ``zmp.png`` and the
report.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit.io import check_zmp_finite, read_feet_yaml, read_ft_source
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N, SensorMount, ZmpSeries

__all__ = ["ZmpRunResult", "run_zmp_log"]


@dataclass(frozen=True)
class ZmpRunResult:
    """What ``zmpkit zmp`` produced.

    Attributes:
        series: the measured ZMP in the world frame.
        log_path: the log it was read from.
        log_source: the log as its reader names it (the figure's title).
        feet_source: where the sensor mounts came from (the report states it).
        contact_threshold_n: the contact threshold used [N].
        started_s: when the run started [s since the epoch].
        files: the files written by role: ``csv`` (``zmp.csv``, empty cells where the ZMP is
            undefined), ``figure`` (``zmp.png``), ``report``; empty until
            :func:`~zmpkit.pipelines.zmp_log_files.write_zmp_log`.
    """

    series: ZmpSeries
    log_path: Path
    log_source: str
    feet_source: str
    contact_threshold_n: float
    started_s: float = field(default_factory=time.time)
    files: dict[str, Path] = field(default_factory=dict)


def run_zmp_log(
    log_path: str | Path,
    *,
    feet: Mapping[str, SensorMount] | None = None,
    feet_path: str | Path | None = None,
    feet_source: str | None = None,
    columns_path: str | Path | None = None,
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N,
    right_topic: str | None = None,
    left_topic: str | None = None,
    units_path: str | Path | None = None,
    time_source: str = "header",
) -> ZmpRunResult:
    """Compute the ZMP of a recorded two-foot F-T log; nothing is written.

    Args:
        log_path: any log :func:`zmpkit.io.read_ft_source` reads: CSV or Parquet with the
            columns of :data:`zmpkit.io.FT_LOG_COLUMNS`, a ROS 2 bag (folder, .db3, .mcap)
            or YARP dumps.
        feet: sensor mounts per foot; or give ``feet_path`` (FEET.yaml) instead.
        feet_path: FEET.yaml with both feet's sensor poses.
        feet_source: where ``feet`` came from, as the report states it (a robot, a file);
            None: ``feet_path``.
        columns_path: optional column-map YAML ``{canonical: header}`` (CSV, Parquet).
        contact_threshold_n: minimum world F_z for a foot to count as in contact [N], in
            :data:`zmpkit.sensors.CONTACT_THRESHOLD_RANGE_N`.
        right_topic: the right foot's WrenchStamped topic (bags) or port (YARP).
        left_topic: the left foot's WrenchStamped topic (bags) or port (YARP).
        units_path: optional units YAML (:func:`zmpkit.io.read_log_units`): axis order,
            signs, units and mounting rotation of each sensor.
        time_source: "header" (sensor stamps, default) or "receive" (bags, YARP).

    Every input is read and the ZMP computed (and checked finite) before anything is
    written, so a run that fails on its inputs leaves nothing behind.
    """
    started_s = time.time()
    mounts = _mounts(feet, feet_path)
    log = read_ft_source(
        log_path,
        right_topic=right_topic,
        left_topic=left_topic,
        column_map=columns_path,
        units=units_path,
        time_source=time_source,
    )
    series = log.zmp_series(mounts, contact_threshold_n)
    check_zmp_finite(series)
    return ZmpRunResult(
        series=series,
        log_path=Path(log_path),
        log_source=log.source,
        feet_source=f"{feet_path}" if feet_source is None else feet_source,
        contact_threshold_n=contact_threshold_n,
        started_s=started_s,
    )


def _mounts(
    feet: Mapping[str, SensorMount] | None, feet_path: str | Path | None
) -> Mapping[str, SensorMount]:
    """The sensor mounts per foot: ``feet``, or read from ``feet_path`` (exactly one given)."""
    if (feet is None) == (feet_path is None):
        raise ValueError("give exactly one of feet and feet_path")
    if feet is not None:
        return feet
    assert feet_path is not None  # exactly one of the two is given
    return read_feet_yaml(feet_path)
