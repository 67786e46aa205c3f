"""Rich progress displays on stderr, each usable as a pipeline's progress callback.

Every display is a context manager (``with ... as progress:``) and the instance itself is
the callback the pipeline takes; they differ only in what the callback receives.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TaskID, TimeElapsedColumn

__all__ = [
    "GenerationProgress",
    "RichDisplays",
    "SimTimeProgress",
    "StageProgress",
    "SweepProgress",
    "TrialProgressBar",
]

_COUNT = MofNCompleteColumn


class _Display:
    """A rich display with a description, a bar, ``middle`` columns and the elapsed time."""

    def __init__(self, *middle: Any) -> None:
        self._bar = Progress(
            "[progress.description]{task.description}",
            BarColumn(),
            *middle,
            TimeElapsedColumn(),
            console=Console(stderr=True),
        )

    def __enter__(self) -> Any:
        self._bar.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._bar.stop()


class TrialProgressBar(_Display):
    """One sweep's bar; the instance is a ``progress(finished, total, target_m)``.

    Args:
        total: number of trials.
    """

    def __init__(self, total: int) -> None:
        super().__init__(_COUNT())
        self._task = self._bar.add_task("trials", total=total)

    def __call__(self, finished: int, total: int, target_m: float) -> None:
        """Show ``finished`` of ``total`` trials; ``target_m`` is the last one's target [m]."""
        self._bar.update(
            self._task, completed=finished, total=total, description=f"target {target_m:g} m"
        )


class SweepProgress(_Display):
    """A bar per sweep.

    The instance is a ``progress(label, total)`` factory returning that sweep's
    ``progress(finished, total, target_m)`` callback.
    """

    def __init__(self) -> None:
        super().__init__(_COUNT())

    def __call__(self, label: str, total: int) -> Callable[[int, int, float], None]:
        """A new bar named ``label`` for ``total`` trials, and its callback."""
        task = self._bar.add_task(label, total=total)

        def update(finished: int, total: int, target_m: float) -> None:
            self._bar.update(task, completed=finished, total=total)

        return update


class _LazyDisplay(_Display):
    """A display that appears with its first update.

    An input error found before any work then prints its one line alone.
    """

    def __init__(self, *middle: Any) -> None:
        super().__init__(*middle)
        self._started = False

    def __enter__(self) -> Any:
        return self

    def __exit__(self, *exc: object) -> None:
        if self._started:
            self._bar.stop()

    def _show(self) -> None:
        if not self._started:
            self._bar.start()
            self._started = True


class SimTimeProgress(_LazyDisplay):
    """A bar of simulated seconds; the instance is a ``progress(simulated_s, total_s)``.

    It appears with the first simulated step, so a walk refused before it is simulated (a
    plan the robot cannot follow) prints its one line alone.
    """

    def __init__(self, label: str) -> None:
        super().__init__("{task.completed:.1f}/{task.total:.1f} s simulated")
        self._task = self._bar.add_task(label, total=0.0)

    def __call__(self, simulated_s: float, total_s: float) -> None:
        """Show ``simulated_s`` of ``total_s`` simulated seconds."""
        self._show()
        self._bar.update(self._task, completed=simulated_s, total=total_s)


class StageProgress(_Display):
    """One bar per named stage; the instance is a ``progress(stage, finished, total)``."""

    def __init__(self) -> None:
        super().__init__(_COUNT())
        self._tasks: dict[str, TaskID] = {}

    def __call__(self, stage: str, finished: int, total: int) -> None:
        """Show ``finished`` of ``total`` steps of ``stage`` (a new bar for a new stage)."""
        if stage not in self._tasks:
            self._tasks[stage] = self._bar.add_task(stage, total=total)
        self._bar.update(self._tasks[stage], completed=finished, total=total)


class GenerationProgress(_LazyDisplay):
    """A bar of CMA-ES generations with the best cost and ETA.

    The instance is the fit's ``progress(FitProgress)`` callback. It appears with the first
    finished generation, so an input error before the fit starts prints alone.
    """

    def __init__(self, label: str = "fit") -> None:
        super().__init__(_COUNT(), "best cost {task.fields[best]}", "ETA {task.fields[eta]}")
        self._task = self._bar.add_task(label, total=None, best="–", eta="–")
        self._label = label
        self._replicas: TaskID | None = None

    def __call__(self, progress: Any) -> None:
        """Show one finished generation (a ``FitProgress``)."""
        self._show()
        restart = getattr(progress, "restart", 0)
        label = f"{self._label} (restart {restart}, {progress.popsize})" if restart else self._label
        self._bar.update(
            self._task,
            description=label,
            completed=progress.generation,
            total=progress.generations,
            best=f"{progress.best_cost:.4g}",
            eta=f"{progress.eta_s:.0f} s",
        )

    def replicas(self, finished: int, total: int) -> None:
        """Show ``finished`` of ``total`` interval replicas recorded again and re-fitted."""
        self._show()
        if self._replicas is None:
            self._replicas = self._bar.add_task("interval replicas", total=total, best="–", eta="–")
        self._bar.update(self._replicas, completed=finished, total=total)


class RichDisplays:
    """The rich displays of a composed run (:class:`zmpkit.pipelines.progress.Displays`)."""

    def sweeps(self) -> SweepProgress:
        """A bar per sweep of trials."""
        return SweepProgress()

    def simulation(self, label: str) -> SimTimeProgress:
        """A bar of simulated seconds."""
        return SimTimeProgress(label)

    def stages(self) -> StageProgress:
        """A bar per named stage."""
        return StageProgress()
