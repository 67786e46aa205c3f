"""``report.html``: a :class:`~zmpkit.analysis.report_document.ReportDocument` as one page.

The page opens offline in any browser: its style is inline, figures are embedded as data URIs
(PNG), and videos are linked beside it (an MP4 is played by the ``<video>`` element; a GIF or
keyframe strip that stands in for one is shown as an image). Text blocks are Markdown rendered
by markdown-it (CommonMark with pipe tables); the page itself is a Jinja2 template with
autoescaping, so no value of a run can inject markup.
"""

from __future__ import annotations

import base64
import os
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import jinja2
from markdown_it import MarkdownIt
from markupsafe import Markup

import zmpkit
from zmpkit.analysis.report_document import (
    Figure,
    ReportDocument,
    Section,
    Table,
    Text,
    Video,
)

__all__ = ["REPORT_HTML", "render_html", "write_html"]

REPORT_HTML = "report.html"
_MARKDOWN = MarkdownIt("commonmark", {"html": False}).enable("table")
_ENV = jinja2.Environment(
    loader=jinja2.PackageLoader("zmpkit.analysis", "templates"),
    autoescape=True,
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
)
_NUMERIC = re.compile(r"^[−+-]?[\d.,]+(e[−+-]?\d+)?\s*[%†*]?$")
_MIME = {".png": "image/png", ".gif": "image/gif", ".jpg": "image/jpeg", ".svg": "image/svg+xml"}


def write_html(doc: ReportDocument, out_dir: str | Path, *, embed_images: bool = True) -> Path:
    """Write ``doc`` as ``report.html`` in ``out_dir`` and return its path.

    Args:
        doc: the report.
        out_dir: the run's folder; linked files are written relative to it.
        embed_images: embed figures as data URIs (True: the page stands alone) or link them.
    """
    path = Path(out_dir) / REPORT_HTML
    path.write_text(render_html(doc, path.parent, embed_images=embed_images), encoding="utf-8")
    return path


def render_html(doc: ReportDocument, base: Path, *, embed_images: bool = True) -> str:
    """The page of ``doc``, with linked files relative to ``base`` (the page's folder)."""
    counters = {"figure": 0, "video": 0, "table": 0}
    renderer = _Renderer(base, embed_images, counters)
    sections = [
        renderer.section(s, level=2, anchor=f"s{i + 1}") for i, s in enumerate(doc.sections)
    ]
    return _ENV.get_template("report.html.j2").render(
        doc=doc,
        version=zmpkit.__version__,
        summary_html=_markdown(doc.summary),
        title_html=_inline(doc.title),
        checks=[
            {"status": c.status, "name": _inline(c.name), "detail": _inline(c.detail)}
            for c in doc.checks
        ],
        sections=sections,
        parts=[(title, _relative(path, base)) for title, path in doc.parts],
        provenance=doc.provenance.rows() if doc.provenance else None,
    )


def _markdown(text: str) -> Markup:
    return Markup(_MARKDOWN.render(text))


def _inline(text: str) -> Markup:
    return Markup(_MARKDOWN.renderInline(text))


def _relative(path: Path, base: Path) -> str:
    return Path(os.path.relpath(Path(path).resolve(), base.resolve())).as_posix()


@dataclass
class _Renderer:
    base: Path
    embed_images: bool
    counters: dict[str, int]

    def section(self, section: Section, level: int, anchor: str) -> dict[str, Any]:
        return {
            "title": _inline(section.title),
            "level": min(level, 6),
            "anchor": anchor,
            "blocks": [self.block(b) for b in section.blocks],
            "subsections": [
                self.section(s, level + 1, f"{anchor}-{i + 1}")
                for i, s in enumerate(section.subsections)
            ],
        }

    def block(self, block: Text | Figure | Video | Table) -> dict[str, Any]:
        if isinstance(block, Text):
            return {"kind": "text", "html": _markdown(block.markdown)}
        if isinstance(block, Figure):
            return {
                "kind": "figure",
                "number": self._next("figure"),
                "src": self._image_src(block.path),
                "alt": block.caption.split(".")[0],
                "caption_html": _inline(block.caption),
            }
        if isinstance(block, Video):
            return {
                "kind": "video",
                "number": self._next("video"),
                "src": _relative(block.path, self.base),
                "is_video": block.path.suffix.lower() in {".mp4", ".webm"},
                "alt": block.caption.split(".")[0],
                "caption_html": _inline(block.caption),
            }
        return {
            "kind": "table",
            "number": self._next("table"),
            "columns": block.columns,
            "rows": [
                [{"text": cell, "numeric": bool(_NUMERIC.match(cell))} for cell in row]
                for row in block.rows
            ],
            "caption_html": _inline(block.caption),
            "notes_html": _markdown(block.notes) if block.notes else "",
        }

    def _next(self, kind: str) -> int:
        self.counters[kind] += 1
        return self.counters[kind]

    def _image_src(self, path: Path) -> str:
        mime = _MIME.get(path.suffix.lower())
        if not self.embed_images or mime is None or not path.is_file():
            return _relative(path, self.base)
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        return f"data:{mime};base64,{data}"
