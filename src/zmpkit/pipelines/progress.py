"""How a pipeline reports progress: the callbacks it takes, and displays that show nothing.

Pipelines only call these; what shows them (rich bars on a terminal) belongs to the CLI
(:mod:`zmpkit.cli.progress`). A composed run such as the demo takes a :class:`Displays`,
which opens one display per stage.
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import AbstractContextManager, nullcontext
from typing import Protocol

__all__ = [
    "SILENT",
    "Displays",
    "SimTimeCallback",
    "StageCallback",
    "SweepCallback",
    "SweepFactory",
]

SweepCallback = Callable[[int, int, float], None]
"""``progress(finished, total, target_m)`` of one sweep of trials."""
SweepFactory = Callable[[str, int], SweepCallback]
"""``progress(label, total)``: a new sweep's callback."""
SimTimeCallback = Callable[[float, float], None]
"""``progress(simulated_s, total_s)`` of one simulation [s]."""
StageCallback = Callable[[str, int, int], None]
"""``progress(stage, finished, total)`` of a run in named stages."""


class Displays(Protocol):
    """Opens a progress display per stage of a composed run; each yields its callback."""

    def sweeps(self) -> AbstractContextManager[SweepFactory]:
        """A display for trial sweeps."""
        ...

    def simulation(self, label: str) -> AbstractContextManager[SimTimeCallback]:
        """A display for one simulation named ``label``."""
        ...

    def stages(self) -> AbstractContextManager[StageCallback]:
        """A display for a run in named stages."""
        ...


def _ignore(*_: object) -> None:
    """A callback that shows nothing."""


def _silent_sweep(label: str, total: int) -> SweepCallback:
    """A sweep callback that shows nothing."""
    return _ignore


class _Silent:
    """Displays that show nothing (the default of a pipeline called from Python)."""

    def sweeps(self) -> AbstractContextManager[SweepFactory]:
        return nullcontext(_silent_sweep)

    def simulation(self, label: str) -> AbstractContextManager[SimTimeCallback]:
        return nullcontext(_ignore)

    def stages(self) -> AbstractContextManager[StageCallback]:
        return nullcontext(_ignore)


SILENT: Displays = _Silent()
"""Displays that show nothing."""
