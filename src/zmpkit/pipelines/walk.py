"""The ``zmpkit walk`` pipeline: pattern → whole-body IK → the virtual robot walks → report.

:func:`run_walk` runs the walk experiment (:mod:`zmpkit.experiments.walk`);
:func:`~zmpkit.pipelines.walk_files.write_walk` writes its folder:
:data:`~zmpkit.experiments.walk_dataset.SUMMARY_FILE` (the
:class:`~zmpkit.experiments.walk_summary.WalkSummary` as JSON),
:data:`~zmpkit.experiments.walk_dataset.SERIES_FILE` (one row per 10 ms frame), the figures
of :mod:`zmpkit.analysis.walk_plots`, with ``config.video`` the video ``walk.mp4``
(:mod:`zmpkit.analysis.walk_video`), and the report. Metrics are taken over the steady walk:
from the end of the second step to one step before the last one ends (or the fall).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import WalkSummary
from zmpkit.experiments.walk_trial import ProgressCallback, WalkRecord
from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["WalkResult", "run_walk"]


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
