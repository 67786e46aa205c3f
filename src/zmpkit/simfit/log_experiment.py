"""Walk logs as experiments: which paths are logs, their windows, the report's sentence.

A walk log (:mod:`zmpkit.experiments.walk_log`) is a ``.csv`` or ``.parquet`` file, or a
folder holding :data:`~zmpkit.experiments.walk_log.WALK_LOG_FILE` and no ``summary.json``
(a ``zmpkit walk`` folder is re-simulated from its command instead); it is fitted by
multiple shooting (:mod:`~zmpkit.simfit.shooting_window`), each window one experiment.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from zmpkit.errors import InputFileError
from zmpkit.experiments.walk_dataset import SUMMARY_FILE
from zmpkit.experiments.walk_log import WALK_LOG_FILE, read_walk_log
from zmpkit.robots.robot import Robot
from zmpkit.simfit.shooting_window import ShootingWindow, log_windows

__all__ = ["LOG_SUFFIXES", "read_log_windows", "shooting_summary", "walk_log_path"]

LOG_SUFFIXES = (".csv", ".parquet")
"""A walk log's file suffixes."""


def walk_log_path(path: Path, walk_folders: bool = False) -> Path | None:
    """The walk log ``path`` names (itself, or a folder's :data:`WALK_LOG_FILE`), or None.

    A ``zmpkit walk`` folder (it holds ``summary.json``) is no log: its walk is re-simulated
    from its command (:mod:`~zmpkit.simfit.experiments`); pass its ``walk_log.csv`` to fit
    the log instead. With ``walk_folders`` (a robot whose fit replays steps, not walks) such
    a folder's log is returned: its walk is fitted by multiple shooting.
    """
    if path.suffix in LOG_SUFFIXES and not path.is_dir():
        return path
    if path.is_dir() and (walk_folders or not (path / SUMMARY_FILE).exists()):
        for suffix in LOG_SUFFIXES:
            found = path / Path(WALK_LOG_FILE).with_suffix(suffix).name
            if found.exists():
                return found
    return None


def read_log_windows(
    path: Path, robot: Robot, window_s: float, burn_in_s: float
) -> list[ShootingWindow]:
    """:func:`log_windows` of the walk log at ``path``.

    Raises:
        InputFileError: on a log that cannot be read, or gives no window.
    """
    if not path.exists():
        raise InputFileError(path, "the walk log does not exist")
    name = path.parent.name if path.name.startswith("walk_log") else path.stem
    return log_windows(read_walk_log(path), robot, name or path.stem, window_s, burn_in_s)


def shooting_summary(experiments: Sequence[object]) -> str:
    """One sentence for a report: which logs were fitted by multiple shooting, and how.

    Empty when none of ``experiments`` is a :class:`ShootingWindow`.
    """
    windows = [e for e in experiments if isinstance(e, ShootingWindow)]
    if not windows:
        return ""
    logs = ", ".join(dict.fromkeys(w.log_name for w in windows))
    length = windows[0].command_time_s[-1] - windows[0].command_time_s[0]
    return (
        f"The walk log {logs} was fitted by multiple shooting with {len(windows)} windows of "
        f"{length:.2g} s, each replayed open loop on its recorded commands from the state its "
        f"sensors measured, its first {windows[0].burn_in_s:g} s not scored."
    )
