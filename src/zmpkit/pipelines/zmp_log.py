"""The ``zmpkit zmp`` pipeline: an F-T log in, the measured ZMP out (CSV + figure)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from zmpkit.analysis.zmp_plot import plot_zmp_series
from zmpkit.io import check_zmp_finite, read_feet_yaml, read_ft_source, write_zmp_csv
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N, SensorMount, ZmpSeries

__all__ = ["ZmpRunResult", "run_zmp_log"]


@dataclass(frozen=True)
class ZmpRunResult:
    """What ``zmpkit zmp`` produced.

    Attributes:
        series: the measured ZMP in the world frame.
        csv_path: ``zmp.csv`` (empty cells where the ZMP is undefined).
        figure_path: ``zmp.png``.
    """

    series: ZmpSeries
    csv_path: Path
    figure_path: Path


def run_zmp_log(
    log_path: str | Path,
    out_dir: str | Path,
    *,
    feet: Mapping[str, SensorMount] | None = None,
    feet_path: str | Path | None = None,
    columns_path: str | Path | None = None,
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N,
    right_topic: str | None = None,
    left_topic: str | None = None,
    units_path: str | Path | None = None,
    time_source: str = "header",
) -> ZmpRunResult:
    """Compute the ZMP of a recorded two-foot F-T log and write ``zmp.csv`` and ``zmp.png``.

    Args:
        log_path: any log :func:`zmpkit.io.read_ft_source` reads: CSV or Parquet with the
            columns of :data:`zmpkit.io.FT_LOG_COLUMNS`, a ROS 2 bag (folder, .db3, .mcap)
            or YARP dumps.
        out_dir: output folder, created if missing.
        feet: sensor mounts per foot; or give ``feet_path`` (FEET.yaml) instead.
        feet_path: FEET.yaml with both feet's sensor poses.
        columns_path: optional column-map YAML ``{canonical: header}`` (CSV, Parquet).
        contact_threshold_n: minimum world F_z for a foot to count as in contact [N], in
            :data:`zmpkit.sensors.CONTACT_THRESHOLD_RANGE_N`.
        right_topic: the right foot's WrenchStamped topic (bags) or port (YARP).
        left_topic: the left foot's WrenchStamped topic (bags) or port (YARP).
        units_path: optional units YAML (:func:`zmpkit.io.read_log_units`): axis order,
            signs, units and mounting rotation of each sensor.
        time_source: "header" (sensor stamps, default) or "receive" (bags, YARP).

    Every input is read and the ZMP computed (and checked finite) before ``out_dir`` is
    created, so a run that fails on its inputs leaves nothing behind. A figure that cannot be
    drawn is a :class:`~zmpkit.errors.FigureWarning` and a placeholder image, not an error.
    """
    if (feet is None) == (feet_path is None):
        raise ValueError("give exactly one of feet and feet_path")
    if feet is not None:
        mounts: Mapping[str, SensorMount] = feet
    else:
        assert feet_path is not None  # exactly one of the two is given
        mounts = read_feet_yaml(feet_path)
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
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    csv_path = write_zmp_csv(series, out / "zmp.csv")
    figure_path = plot_zmp_series(series, out / "zmp.png", title=f"Measured ZMP: {log.source}")
    return ZmpRunResult(series=series, csv_path=csv_path, figure_path=figure_path)
