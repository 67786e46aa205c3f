"""``pipelines/`` keeps one convention: ``run_x`` computes, ``write_x`` writes, short functions.

Per command: ``x.py`` runs (``run_x(config) -> XResult``; it writes only what a long run
writes as it goes: datasets, checkpoints), ``x_document.py`` builds the one report, and
``x_files.py`` writes the files, figures, videos and the report (``write_x(result, out)``).
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PIPELINES = Path(__file__).resolve().parents[2] / "src" / "zmpkit" / "pipelines"
MAX_FUNCTION_LINES = 60
DRAWING = ("zmpkit.analysis.report_files", "zmpkit.analysis.video", "zmpkit.analysis.walk_video")
"""Modules that write reports and videos: only the write step imports them."""


def _modules() -> list[Path]:
    return sorted(p for p in PIPELINES.glob("*.py") if p.name != "__init__.py")


def _imports(tree: ast.Module) -> set[str]:
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module is not None:
            found.add(node.module)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return found


def test_no_report_module_of_three_meanings() -> None:
    """A file says what it does: ``*_document.py``, ``*_files.py``, ``*_figures.py``."""
    assert [p.name for p in _modules() if p.name.endswith("_report.py")] == []


@pytest.mark.parametrize("path", _modules(), ids=lambda p: p.name)
def test_functions_are_at_most_60_lines(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    long = [
        f"{node.name}: {node.end_lineno - node.lineno + 1} lines"
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        and node.end_lineno is not None
        and node.end_lineno - node.lineno + 1 > MAX_FUNCTION_LINES
    ]
    assert long == []


def _run_modules() -> list[Path]:
    """The modules that define a ``run_x`` function."""
    return [
        path
        for path in _modules()
        if any(
            isinstance(node, ast.FunctionDef) and node.name.startswith("run_")
            for node in ast.parse(path.read_text(encoding="utf-8")).body
        )
    ]


@pytest.mark.parametrize("path", _run_modules(), ids=lambda p: p.name)
def test_a_run_module_draws_and_reports_nothing(path: Path) -> None:
    """A module with a ``run_x`` imports no plotting, report or video writer."""
    imports = _imports(ast.parse(path.read_text(encoding="utf-8")))
    drawing = sorted(m for m in imports if m in DRAWING or m.endswith(("_plot", "_plots")))
    assert drawing == [], f"{path.name} imports {drawing}"


@pytest.mark.slow
def test_walk_does_not_import_the_balance_pipeline() -> None:
    """``zmpkit walk`` loads neither the balance pipeline nor its video, even indirectly."""
    code = (
        "import sys, zmpkit.pipelines.walk_files, zmpkit.cli.walk; "
        "print(sorted(m for m in sys.modules if m.startswith('zmpkit.pipelines.balance')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "[]"
