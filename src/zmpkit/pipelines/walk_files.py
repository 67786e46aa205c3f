"""The files of ``zmpkit walk``: summary, time series, sensor log, figures, video, report.

The sensor log (:data:`~zmpkit.experiments.walk_log.WALK_LOG_FILE`: every driven joint's
command and encoder, the IMU, both feet's F-T) is what a robot's own log holds; ``zmpkit
identify sim`` fits it by multiple shooting as a walk of an unknown controller.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.walk_video import (
    SIDE_BY_SIDE_FILE,
    WALK_VIDEO_FILE,
    write_walk_video,
    write_walks_side_by_side,
)
from zmpkit.experiments.walk_dataset import SERIES_FILE, SUMMARY_FILE, write_series, write_summary
from zmpkit.experiments.walk_log import WALK_LOG_FILE, walk_log_from_record, write_walk_log
from zmpkit.pipelines.walk import WalkResult
from zmpkit.pipelines.walk_document import walk_document
from zmpkit.pipelines.walk_figures import series_joints, write_figures

__all__ = ["SIDE_BY_SIDE_FILE", "write_side_by_side", "write_walk"]


def write_walk(result: WalkResult, out_dir: str | Path, report_format: str = "html") -> WalkResult:
    """Write a walk's summary, time series, figures, video (as its config asks) and report.

    Args:
        result: the walk, from :func:`~zmpkit.pipelines.walk.run_walk`.
        out_dir: output folder (created if missing).
        report_format: ``html`` (``report.html``), ``md`` (``report.md``) or ``both``.

    Returns:
        ``result`` with the files written, by role (``"report"``: the report).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = {
        "summary": write_summary(out / SUMMARY_FILE, result.summary),
        "series": write_series(
            out / SERIES_FILE, result.pattern, result.record, series_joints(result.config)
        ),
    }
    if result.record.sensors is not None and set(result.record.feet) == {"right", "left"}:
        files["log"] = write_walk_log(out / WALK_LOG_FILE, walk_log_from_record(result.record))
    if result.config.figures:
        files.update(
            write_figures(out, result.config, result.pattern, result.record, result.summary)
        )
    if result.config.video:
        video = write_walk_video(result.config, result.record, out / WALK_VIDEO_FILE)
        if video.path is not None:
            files["video"] = video.path
    written = replace(result, files=files)
    files["report"] = write_report(walk_document(written), out, report_format)
    return replace(result, files=files)


def write_side_by_side(walks: Sequence[WalkResult], out_dir: str | Path) -> Path | None:
    """Draw walks side by side into ``out_dir`` (:data:`SIDE_BY_SIDE_FILE`), labelled by effects.

    Returns:
        What was written (the MP4, or the GIF or keyframes written instead), or None.
    """
    records = [(w.config, w.record) for w in walks]
    return write_walks_side_by_side(records, Path(out_dir) / SIDE_BY_SIDE_FILE).path
