"""The ``zmpkit walk`` pipeline: pattern → whole-body IK → the virtual robot walks → report.

:func:`run_walk` runs the walk experiment (:mod:`zmpkit.experiments.walk`); :func:`write_walk`
writes its folder: :data:`~zmpkit.experiments.walk_dataset.SUMMARY_FILE` (the
:class:`~zmpkit.experiments.walk_summary.WalkSummary` as JSON),
:data:`~zmpkit.experiments.walk_dataset.SERIES_FILE` (one row per 10 ms frame) and the figures
of :mod:`zmpkit.analysis.walk_plots`, and with ``config.video`` the video ``walk.mp4``
(:mod:`zmpkit.analysis.walk_video`). Metrics are taken over the steady walk: from the end of
the second step to one step before the last one ends (or the fall).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from zmpkit.analysis.walk_video import WALK_VIDEO_FILE, write_walk_video
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_dataset import SERIES_FILE, SUMMARY_FILE, write_series, write_summary
from zmpkit.experiments.walk_summary import WalkSummary
from zmpkit.experiments.walk_trial import ProgressCallback, WalkRecord
from zmpkit.pipelines.walk_figures import series_joints, write_figures
from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["WalkResult", "run_walk", "write_walk"]


@dataclass(frozen=True)
class WalkResult:
    """What a walk produced.

    Attributes:
        config: what was asked.
        summary: the metrics written to ``summary.json``.
        pattern: the planned walk.
        trajectory: the IK's joint angles and errors.
        record: the simulated signals.
        files: every file written, by role (empty until :func:`write_walk`); ``"video"`` is
            the walk's video (``walk.mp4``, or the GIF or keyframes written instead).
        started_s: when the run started [s since the epoch].
    """

    config: WalkConfig
    summary: WalkSummary
    pattern: WalkingPattern
    trajectory: JointTrajectory
    record: WalkRecord
    files: dict[str, Path] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)


def run_walk(config: WalkConfig, progress: ProgressCallback | None = None) -> WalkResult:
    """Plan, solve the IK, simulate and analyse one walk.

    Args:
        config: the walk.
        progress: called with (simulated time, total time) [s] during the simulation.

    Returns:
        The summary and the signals; nothing is written.

    Raises:
        ParameterError: before simulating, on a plan the robot's legs cannot follow
            (:func:`~zmpkit.experiments.walk.check_realisable`).
    """
    started_s = time.time()
    trial = run_walk_trial(config, progress, realisable_only=True)
    return WalkResult(
        config, trial.summary, trial.pattern, trial.trajectory, trial.record, started_s=started_s
    )


def write_walk(result: WalkResult, out_dir: str | Path) -> WalkResult:
    """Write a walk's summary, time series, figures and video (as its config asks) to ``out_dir``.

    Args:
        result: the walk, from :func:`run_walk`.
        out_dir: output folder (created if missing).

    Returns:
        ``result`` with the files written, by role.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = {
        "summary": write_summary(out / SUMMARY_FILE, result.summary),
        "series": write_series(
            out / SERIES_FILE, result.pattern, result.record, series_joints(result.config)
        ),
    }
    if result.config.figures:
        files.update(
            write_figures(out, result.config, result.pattern, result.record, result.summary)
        )
    if result.config.video:
        video = write_walk_video(result.config, result.record, out / WALK_VIDEO_FILE)
        if video.path is not None:
            files["video"] = video.path
    return replace(result, files=files)
