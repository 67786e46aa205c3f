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

__all__ = [
    "base_parser",
    "best_of",
    "environment",
    "pin_threads",
    "print_table",
    "write_json",
    "write_run",
]

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
        "cpus_used": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
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


class _BenchParser(argparse.ArgumentParser):
    """An argument parser that pins the process to ``--threads`` CPUs once it has parsed."""

    def parse_args(self, args=None, namespace=None):  # type: ignore[override]
        parsed = super().parse_args(args, namespace)
        if parsed.threads is not None:
            try:
                pin_threads(parsed.threads)
            except ValueError as error:
                self.error(str(error))
        return parsed


def pin_threads(n: int) -> None:
    """Run this process and every thread it starts later on its first ``n`` CPUs.

    A benchmark's ratios then compare what ``n`` cores do, whatever the machine has (CPU
    affinity, which the MuJoCo thread pools and BLAS inherit); ``environment()`` reports it
    as ``cpus_used``.
    """
    if not hasattr(os, "sched_setaffinity"):
        raise ValueError("--threads needs CPU affinity, which this system lacks (Linux has it)")
    available = sorted(os.sched_getaffinity(0))
    if not 1 <= n <= len(available):
        raise ValueError(f"--threads must be an integer in [1, {len(available)}]; got {n}")
    os.sched_setaffinity(0, set(available[:n]))


def base_parser(description: str) -> argparse.ArgumentParser:
    """An argument parser with ``--json PATH`` and ``--threads N`` (pin to N CPUs)."""
    parser = _BenchParser(description=description)
    parser.add_argument("--json", type=Path, help="write the results to this JSON file")
    parser.add_argument(
        "--threads", type=int, help="run on this many CPUs only (default: all it may use)"
    )
    return parser
