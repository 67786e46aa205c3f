"""Scaffolding shared by the ``bench_*.py`` scripts: environment, timing, table, JSON, CLI.

The scripts are run as ``python benchmarks/bench_x.py``, which puts this folder first on
``sys.path``, so they import it as ``from harness import ...``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import timeit
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
import scipy

__all__ = ["base_parser", "best_of", "environment", "print_table", "write_json", "write_run"]

Justify = Literal["default", "left", "center", "right", "full"]


def environment() -> dict[str, Any]:
    """Where the benchmark ran: Python, numpy and scipy versions, machine, processor, CPUs.

    ``python`` is the implementation and version (``"CPython 3.11.7"``); ``python_version``
    is the version alone.
    """
    return {
        "python": platform.python_implementation() + " " + platform.python_version(),
        "python_version": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "machine": platform.machine(),
        "processor": platform.processor(),
        "cpu_count": os.cpu_count(),
    }


def best_of(
    stmt: str | Callable[[], object],
    number: int,
    repeat: int,
    namespace: dict[str, Any] | None = None,
) -> float:
    """Best time of one execution of ``stmt`` over ``repeat`` runs of ``number`` calls [s].

    ``stmt`` is a callable, or a statement string evaluated in ``namespace``; a string is
    inlined in :mod:`timeit`'s loop and so is not charged the cost of an extra call.
    """
    timer = timeit.Timer(stmt, globals=namespace)
    return min(timer.repeat(repeat=repeat, number=number)) / number


def print_table(
    title: str,
    columns: Sequence[str],
    rows: Sequence[Sequence[str]],
    justify: Sequence[Justify] | None = None,
) -> None:
    """Print ``rows`` under ``columns`` as a rich table, or as plain ``a | b`` lines.

    Text is printed literally (square brackets are not read as rich markup). ``justify``
    gives each column's alignment (rich only; left by default).
    """
    try:
        from rich.console import Console
        from rich.markup import escape
        from rich.table import Table
    except ImportError:
        print(title)
        for line in (columns, *rows):
            print(" | ".join(line))
        return
    table = Table(title=escape(title))
    for i, column in enumerate(columns):
        table.add_column(escape(column), justify=justify[i] if justify else "left")
    for row in rows:
        table.add_row(*(escape(cell) for cell in row))
    Console().print(table)


def write_json(path: Path, results: dict[str, Any]) -> None:
    """Write ``results`` to ``path`` as indented JSON (UTF-8, trailing newline)."""
    path.write_text(json.dumps(results, indent=2) + "\n", encoding="utf-8")


def write_run(args: argparse.Namespace, results: dict[str, Any]) -> None:
    """If ``args.json`` is set, write the run there: its arguments, the environment (with
    MuJoCo's version) and ``results``."""
    if args.json is None:
        return
    import mujoco

    info = {"mujoco": mujoco.__version__, **environment()}
    run_args = vars(args) | {"json": str(args.json)}
    write_json(args.json, {"args": run_args, "env": info, **results})


def base_parser(description: str) -> argparse.ArgumentParser:
    """An argument parser with ``--json PATH`` (where to write the results, if anywhere)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--json", type=Path, help="write the results to this JSON file")
    return parser
