"""``report.md``: a :class:`~zmpkit.analysis.report_document.ReportDocument` as Markdown.

The same report as :mod:`zmpkit.analysis.report_html`, for a repository or a terminal: the
verdict as a table, then the sections, with figures, videos and tables numbered and captioned
in the same order, files linked relative to the report.
"""

from __future__ import annotations

import os
from pathlib import Path

from zmpkit.analysis.report_document import Figure, ReportDocument, Section, Table, Text, Video

__all__ = ["REPORT_MD", "render_markdown", "write_markdown"]

REPORT_MD = "report.md"


def write_markdown(doc: ReportDocument, out_dir: str | Path) -> Path:
    """Write ``doc`` as ``report.md`` in ``out_dir`` and return its path."""
    path = Path(out_dir) / REPORT_MD
    path.write_text(render_markdown(doc, path.parent), encoding="utf-8")
    return path


def render_markdown(doc: ReportDocument, base: Path) -> str:
    """The Markdown text of ``doc``, with linked files relative to ``base``."""
    counters = {"figure": 0, "video": 0, "table": 0}
    parts = [f"# {doc.title}\n", doc.summary.strip() + "\n", _verdict(doc)]
    if doc.parts:
        links = " · ".join(f"[{title}]({_relative(path, base)})" for title, path in doc.parts)
        parts.append(f"Reports of the parts: {links}\n")
    for section in doc.sections:
        parts.append(_section(section, 2, base, counters))
    if doc.provenance is not None:
        rows = "".join(f"| {k} | `{v}` |\n" for k, v in doc.provenance.rows())
        parts.append(f"## Provenance\n\n| | |\n|---|---|\n{rows}")
    return "\n".join(parts)


def _verdict(doc: ReportDocument) -> str:
    if not doc.checks:
        return f"**Verdict: {doc.status}** — this run states no target.\n"
    rows = "".join(f"| **{c.status}** | {c.name} | {_cell(c.detail)} |\n" for c in doc.checks)
    return (
        f"## Verdict: {doc.status}\n\n| outcome | target | value against its bar, or why |\n"
        f"|---|---|---|\n{rows}"
    )


def _section(section: Section, level: int, base: Path, counters: dict[str, int]) -> str:
    out = [f"{'#' * min(level, 6)} {section.title}\n"]
    for block in section.blocks:
        out.append(_block(block, base, counters))
    for sub in section.subsections:
        out.append(_section(sub, level + 1, base, counters))
    return "\n".join(out)


def _block(block: Text | Figure | Video | Table, base: Path, counters: dict[str, int]) -> str:
    if isinstance(block, Text):
        return block.markdown.strip() + "\n"
    if isinstance(block, Figure):
        n = _next(counters, "figure")
        link = _relative(block.path, base)
        return f"![Figure {n}]({link})\n\n*Figure {n}.* {block.caption}\n"
    if isinstance(block, Video):
        n = _next(counters, "video")
        link = _relative(block.path, base)
        return f"[Video {n}: `{link}`]({link})\n\n*Video {n}.* {block.caption}\n"
    n = _next(counters, "table")
    header = "| " + " | ".join(block.columns) + " |\n|" + "---|" * len(block.columns) + "\n"
    rows = "".join("| " + " | ".join(_cell(c) for c in row) + " |\n" for row in block.rows)
    notes = f"\n{block.notes.strip()}\n" if block.notes else ""
    return f"*Table {n}.* {block.caption}\n\n{header}{rows}{notes}"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _next(counters: dict[str, int], kind: str) -> int:
    counters[kind] += 1
    return counters[kind]


def _relative(path: Path, base: Path) -> str:
    return Path(os.path.relpath(Path(path).resolve(), base.resolve())).as_posix()
