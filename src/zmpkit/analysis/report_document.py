"""A run's report as data: verdict, sections of text, figures, videos and tables, provenance.

Every pipeline describes its report as a :class:`ReportDocument`; the renderers turn it into
a self-contained ``report.html`` (:mod:`zmpkit.analysis.report_html`) or ``report.md``
(:mod:`zmpkit.analysis.report_markdown`). Keeping the report as data lets the demo compose the
reports of its parts, lets tests read a verdict without parsing text, and keeps both formats
saying the same thing.

- :class:`Check` — one target of the run and how it came out: ``met``, ``missed`` or
  ``undefined`` (with why), or ``info`` for a figure stated without a bar.
- :class:`Text` (Markdown), :class:`Figure`, :class:`Video` and :class:`Table` — the blocks of
  a :class:`Section`; every figure, video and table has a caption, and the renderers number
  them (Figure 1, Video 1, Table 1 …) in reading order.
- :class:`~zmpkit.analysis.provenance.Provenance` — what made the run.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Literal

from zmpkit.analysis.provenance import Provenance

__all__ = [
    "STATUSES",
    "Block",
    "Check",
    "Figure",
    "ReportDocument",
    "Section",
    "Status",
    "Table",
    "Text",
    "Video",
    "overall_status",
]

Status = Literal["met", "missed", "undefined", "info"]
STATUSES: tuple[Status, ...] = ("met", "missed", "undefined", "info")


@dataclass(frozen=True)
class Check:
    """One target of a run and its outcome.

    Attributes:
        name: what was asked, e.g. "DLIPM error at 0.10 m, sagittal".
        status: ``met``, ``missed``, ``undefined`` (no value could be measured) or ``info``.
        detail: the value against its bar, or why it is undefined, with units.
    """

    name: str
    status: Status
    detail: str

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"check status {self.status!r}; valid: {', '.join(STATUSES)}")

    def prefixed(self, prefix: str) -> Check:
        """The same check named ``"{prefix}: {name}"`` (a part of a composed report)."""
        return replace(self, name=f"{prefix}: {self.name}")


@dataclass(frozen=True)
class Text:
    """Paragraphs, lists or a small table in Markdown (CommonMark with pipe tables)."""

    markdown: str


@dataclass(frozen=True)
class Figure:
    """An image file and its caption: what it shows, units, and what to look at."""

    path: Path
    caption: str


@dataclass(frozen=True)
class Video:
    """A video file (MP4, or a GIF/PNG stand-in) and its caption."""

    path: Path
    caption: str


@dataclass(frozen=True)
class Table:
    """A table: column headers with units, rows of formatted cells, a caption.

    Attributes:
        columns: header of each column, unit in brackets (``"error [%]"``).
        rows: cells as text, one tuple per row, as many as there are columns.
        caption: what the table shows; the renderers number it.
        notes: Markdown under the table (footnote marks, why a cell is empty).
    """

    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    caption: str
    notes: str = ""

    def __post_init__(self) -> None:
        for row in self.rows:
            if len(row) != len(self.columns):
                raise ValueError(f"a row of {len(row)} cells in a table of {len(self.columns)}")


Block = Text | Figure | Video | Table


@dataclass(frozen=True)
class Section:
    """A titled part of a report: blocks, then subsections one level deeper."""

    title: str
    blocks: tuple[Block, ...] = ()
    subsections: tuple[Section, ...] = ()

    def walk(self) -> Iterator[Block]:
        """Every block of this section and its subsections, in reading order."""
        yield from self.blocks
        for sub in self.subsections:
            yield from sub.walk()


@dataclass(frozen=True)
class ReportDocument:
    """A run's whole report.

    Attributes:
        title: the report's title (the command and what it reproduces).
        summary: Markdown under the title: what ran, in two or three sentences.
        checks: the verdict box: each target of the run and its outcome.
        sections: the body.
        provenance: what made the run (version, command line, robot, truth file …).
    """

    title: str
    summary: str
    checks: tuple[Check, ...]
    sections: tuple[Section, ...]
    provenance: Provenance | None = None
    parts: tuple[tuple[str, Path], ...] = field(default=())

    @property
    def status(self) -> Status:
        """The run's overall outcome: see :func:`overall_status`."""
        return overall_status(self.checks)

    def blocks(self) -> Iterator[Block]:
        """Every block of the report, in reading order."""
        for section in self.sections:
            yield from section.walk()

    def media(self) -> tuple[Path, ...]:
        """The files of every figure and video, in reading order."""
        return tuple(b.path for b in self.blocks() if isinstance(b, Figure | Video))


def overall_status(checks: Iterable[Check]) -> Status:
    """``missed`` if any check missed, else ``undefined`` if any is, else ``met`` (or ``info``).

    A run with no bar at all (only ``info`` checks, or none) is ``info``.
    """
    statuses = {c.status for c in checks}
    for status in ("missed", "undefined", "met"):
        if status in statuses:
            return status
    return "info"
