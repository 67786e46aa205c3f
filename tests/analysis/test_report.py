"""The report as data, rendered to HTML and Markdown: numbering, escaping, verdict, links."""

from __future__ import annotations

import time
from html.parser import HTMLParser
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pytest

from zmpkit.analysis.provenance import capture, file_sha256
from zmpkit.analysis.report_document import (
    Check,
    Figure,
    ReportDocument,
    Section,
    Table,
    Text,
    Video,
    overall_status,
)
from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.report_html import render_html
from zmpkit.analysis.report_markdown import render_markdown
from zmpkit.robots.registry import get_robot


def _png(path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(2, 1))
    ax.plot([0, 1], [0, 1])
    fig.savefig(path)
    plt.close(fig)
    return path


def _doc(tmp_path: Path) -> ReportDocument:
    figure = _png(tmp_path / "a.png")
    return ReportDocument(
        title="zmpkit test <run>",
        summary="What ran: **two** figures.",
        checks=(
            Check("error at 0.10 m", "met", "2.1 % ≤ 3.3 %"),
            Check("settling", "undefined", "did not settle within 60 s (drift 0.4 mm/s)"),
        ),
        sections=(
            Section(
                "First",
                (
                    Text("A paragraph with `code` and <script>alert(1)</script>."),
                    Figure(figure, "One."),
                ),
                (Section("Inner", (Figure(figure, "Two."), Video(tmp_path / "w.mp4", "Walk."))),),
            ),
            Section("Second", (Table(("x [m]", "error [%]"), (("0.10", "2.1"),), "Errors."),)),
        ),
        provenance=capture(
            robot=get_robot("teo"), started_s=time.time() - 2.0, effects="all", seed=3
        ),
    )


class _Collect(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))


def test_html_numbers_figures_in_reading_order_and_escapes_markup(tmp_path):
    html = render_html(_doc(tmp_path), tmp_path)
    assert html.index("Figure 1.") < html.index("Figure 2.")
    assert "Video 1." in html
    assert "Table 1." in html
    assert "<script>" not in html  # Markdown text cannot inject markup
    assert "zmpkit test &lt;run&gt;" in html
    parser = _Collect()
    parser.feed(html)
    images = [a["src"] for t, a in parser.tags if t == "img"]
    assert len(images) == 2
    assert all(src.startswith("data:image/png;base64,") for src in images)
    videos = [a["src"] for t, a in parser.tags if t == "video"]
    assert videos == ["w.mp4"]  # linked beside the page


def test_verdict_box_states_each_check_and_the_worst_outcome(tmp_path):
    doc = _doc(tmp_path)
    assert doc.status == "undefined"
    html = render_html(doc, tmp_path)
    assert 'id="verdict"' in html
    assert "did not settle within 60 s" in html
    assert overall_status([Check("a", "met", ""), Check("b", "missed", "")]) == "missed"
    assert overall_status([Check("a", "info", "")]) == "info"
    assert overall_status([]) == "info"


def test_markdown_says_the_same_with_the_same_numbers(tmp_path):
    text = render_markdown(_doc(tmp_path), tmp_path)
    assert "## Verdict: undefined" in text
    assert "*Figure 1.* One." in text
    assert "*Figure 2.* Two." in text
    assert "*Table 1.* Errors." in text
    assert "| 0.10 | 2.1 |" in text
    assert "[Video 1: `w.mp4`](w.mp4)" in text


def test_provenance_states_version_robot_truth_hash_and_time(tmp_path):
    prov = _doc(tmp_path).provenance
    assert prov is not None
    rows = dict(prov.rows())
    assert rows["robot"] == "teo"
    assert rows["seed"] == "3"
    assert rows["effects"] == "all"
    assert Path(prov.truth_file).is_file()
    assert prov.truth_sha256 == file_sha256(Path(prov.truth_file))
    assert len(prov.truth_sha256) == 64
    assert prov.wall_time_s >= 2.0


def test_write_report_formats(tmp_path):
    doc = _doc(tmp_path)
    assert write_report(doc, tmp_path, "md").name == "report.md"
    assert write_report(doc, tmp_path / "b", "both").name == "report.html"
    assert (tmp_path / "b" / "report.md").is_file()
    with pytest.raises(ValueError, match="valid: html, md, both"):
        write_report(doc, tmp_path, "pdf")


def test_table_rows_must_match_columns():
    with pytest.raises(ValueError, match="a row of 1 cells in a table of 2"):
        Table(("a", "b"), (("1",),), "bad")
    with pytest.raises(ValueError, match="valid: met, missed"):
        Check("x", "passed", "")  # type: ignore[arg-type]
