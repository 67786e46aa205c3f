"""A rich progress bar for trial sweeps, usable as their progress callback."""

from __future__ import annotations

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

__all__ = ["TrialProgressBar"]


class TrialProgressBar:
    """A progress bar on stderr; the instance is a ``progress(finished, total, target_m)``.

    Args:
        total: number of trials.
    """

    def __init__(self, total: int) -> None:
        self._bar = Progress(
            "[progress.description]{task.description}",
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            console=Console(stderr=True),
        )
        self._task = self._bar.add_task("trials", total=total)

    def __enter__(self) -> TrialProgressBar:
        self._bar.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._bar.stop()

    def __call__(self, finished: int, total: int, target_m: float) -> None:
        """Show ``finished`` of ``total`` trials; ``target_m`` is the last one's target [m]."""
        self._bar.update(
            self._task, completed=finished, total=total, description=f"target {target_m:g} m"
        )
