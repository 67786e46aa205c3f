"""Write a run's report in the formats asked: ``report.html`` (default), ``report.md``, both.

``--report html|md|both`` on every command that writes a report maps to :func:`write_report`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from zmpkit.analysis.report_document import ReportDocument
from zmpkit.analysis.report_html import write_html
from zmpkit.analysis.report_markdown import write_markdown

__all__ = ["DEFAULT_REPORT_FORMAT", "REPORT_FORMATS", "ReportFormat", "write_report"]

ReportFormat = Literal["html", "md", "both"]
REPORT_FORMATS: tuple[ReportFormat, ...] = ("html", "md", "both")
DEFAULT_REPORT_FORMAT: ReportFormat = "html"


def write_report(doc: ReportDocument, out_dir: str | Path, fmt: str = "html") -> Path:
    """Write ``doc`` into ``out_dir`` as ``fmt`` and return the main file (HTML when written).

    Raises:
        ValueError: on a format other than html, md or both.
    """
    if fmt not in REPORT_FORMATS:
        raise ValueError(f"report format {fmt!r}; valid: {', '.join(REPORT_FORMATS)}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    markdown = write_markdown(doc, out) if fmt in ("md", "both") else None
    html = write_html(doc, out) if fmt in ("html", "both") else None
    main = html or markdown
    assert main is not None  # one of the two is always written
    return main
