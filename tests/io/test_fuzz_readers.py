"""Fuzzing every reader: only a :class:`~zmpkit.errors.ZmpkitError` may escape, in one line.

Each reader gets a valid file with a few mutations (see :mod:`helpers.fuzz_inputs`) or
garbage: Parquet tables with odd columns, YARP ``data.log`` lines, step manifests, truth
files with a number replaced, FEET.yaml, column maps and units files.
"""

from __future__ import annotations

import re
import tempfile
from collections.abc import Callable
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers.ft_data import FEET_YAML
from helpers.fuzz import Census, reader_problems
from helpers.fuzz_inputs import column_map_yaml, feet_yaml, ft_log_csv, number_text
from zmpkit.io import (
    FT_LOG_COLUMNS,
    read_column_map,
    read_feet_yaml,
    read_ft_source,
    read_log_units,
    read_yarp_dump,
)
from zmpkit.io.step_manifest import read_step_manifest
from zmpkit.robots.teo import DEFAULT_TRUTH_PATH, load_truth

_SETTINGS = {
    "deadline": None,
    "database": None,
    "derandomize": True,
    "suppress_health_check": [HealthCheck.too_slow, HealthCheck.data_too_large],
}
_TRUTH_TEXT = DEFAULT_TRUTH_PATH.read_text(encoding="utf-8")


@st.composite
def parquet_table(draw: st.DrawFn) -> pa.Table:
    """A Parquet table: the F-T columns, some dropped, renamed, retyped or holding odd values."""
    n = draw(st.integers(0, 4))
    columns: dict[str, pa.Array] = {}
    for name in FT_LOG_COLUMNS:
        kind = draw(st.sampled_from(("ok", "ok", "ok", "drop", "floats", "text", "null")))
        values = [0.01 * k if name == "time" else -300.0 + k for k in range(n)]
        if kind == "drop":
            continue
        if kind == "floats" and n:
            values[draw(st.integers(0, n - 1))] = draw(st.floats())
        if kind == "text":
            columns[name] = pa.array([str(v) for v in values])
        elif kind == "null" and n:
            columns[name] = pa.array([None, *values[1:]], type=pa.float64())
        else:
            columns[name] = pa.array(values, type=pa.float64())
    return pa.table(columns) if columns else pa.table({"x": pa.array([1.0])})


@st.composite
def yarp_log(draw: st.DrawFn) -> str:
    """A ``data.log``: ``<seq> <stamp> <6 values>`` lines, some mangled."""
    lines = [f"{k} {100.0 + 0.01 * k:.6f} 1.0 2.0 -300.0 0.1 0.2 0.0" for k in range(4)]
    for _ in range(draw(st.integers(0, 3))):
        k = draw(st.integers(0, len(lines) - 1))
        tokens = lines[k].split()
        j = draw(st.integers(0, len(tokens)))
        mutated = draw(st.one_of(number_text(), st.sampled_from(("(", ")", "((1 2)", ""))))
        tokens[j:j + 1] = [mutated]  # fmt: skip
        lines[k] = " ".join(tokens)
    return "\n".join(lines) + "\n"


@st.composite
def manifest_yaml(draw: st.DrawFn) -> str:
    """A step manifest whose fields are mutated; its one log is a generated CSV."""
    fields = {"plane": "sagittal", "mass_kg": "62.6", "length_m": "0.777"}
    fields.update(startup_window_s="0.5", target_m="0.02", t_step_s="0.01")
    for key in draw(st.lists(st.sampled_from(sorted(fields)), max_size=2)):
        fields[key] = draw(st.one_of(number_text(), st.sampled_from(("frontal", "[]", "{}"))))
    return (
        f"plane: {fields['plane']}\nfeet: feet.yaml\nmass_kg: {fields['mass_kg']}\n"
        f"length_m: {fields['length_m']}\nstartup_window_s: {fields['startup_window_s']}\n"
        f"trials:\n  - {{log: log.csv, target_m: {fields['target_m']}, "
        f"t_step_s: {fields['t_step_s']}}}\n"
    )


@st.composite
def truth_yaml(draw: st.DrawFn) -> str:
    """The shipped TEO truth file with one to three of its numbers replaced."""
    text = _TRUTH_TEXT
    for _ in range(draw(st.integers(1, 3))):
        spans = [m.span() for m in re.finditer(r"(?<![\w.])-?\d+\.?\d*(e-?\d+)?", text)]
        start, stop = spans[draw(st.integers(0, len(spans) - 1))]
        text = text[:start] + draw(number_text()).replace("\n", " ") + text[stop:]
    return text


UNITS_YAML = st.sampled_from(
    (
        "right: {force_unit: N, moment_unit: N*m}\n",
        "right: {force_unit: daN}\nleft: {axes: [x, y, z]}\n",
        "right: {axes: [a, b]}\n",
        "bogus: 1\n",
        "right: 3e-2\n",
        "right: {force_unit: 3e-2}\n",
    )
)


def _write(root: Path, name: str, data: str | bytes) -> Path:
    path = root / name
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data, encoding="utf-8", errors="surrogatepass")
    return path


def _readers() -> dict[str, tuple[st.SearchStrategy, Callable[[Path, object], Callable]]]:
    """Per reader: the strategy of its input, and ``(folder, input) -> call``."""

    def parquet(root: Path, table: object) -> Callable:
        pq.write_table(table, root / "log.parquet")
        return lambda: read_ft_source(root / "log.parquet")

    def manifest(root: Path, case: object) -> Callable:
        text, log = case
        _write(root, "feet.yaml", FEET_YAML)
        _write(root, "log.csv", log.data)
        return lambda: read_step_manifest(_write(root, "steps.yaml", text))

    return {
        "csv": (ft_log_csv(), lambda r, c: lambda: read_ft_source(_write(r, "log.csv", c.data))),
        "parquet": (parquet_table(), parquet),
        "yarp": (yarp_log(), lambda r, t: lambda: read_yarp_dump(_write(r, "data.log", t))),
        "manifest": (st.tuples(manifest_yaml(), ft_log_csv()), manifest),
        "truth": (truth_yaml(), lambda r, t: lambda: load_truth(_write(r, "truth.yaml", t))),
        "feet": (feet_yaml(), lambda r, t: lambda: read_feet_yaml(_write(r, "feet.yaml", t))),
        "columns": (
            st.one_of(column_map_yaml().filter(bool), st.text(max_size=30)),
            lambda r, t: lambda: read_column_map(_write(r, "columns.yaml", t)),
        ),
        "units": (
            st.one_of(UNITS_YAML, st.text(max_size=30)),
            lambda r, t: lambda: read_log_units(_write(r, "units.yaml", t)),
        ),
    }


def _run(reader: str, examples: int) -> Census:
    strategy, prepare = _readers()[reader]
    census = Census(f"reader {reader}")

    @settings(max_examples=examples, **_SETTINGS)
    @given(strategy)
    def fuzz(case: object) -> None:
        with tempfile.TemporaryDirectory() as tmp:
            census.record(reader_problems(prepare(Path(tmp), case), Path(tmp)), case)

    fuzz()
    return census


READERS = ("csv", "parquet", "yarp", "manifest", "truth", "feet", "columns", "units")


@pytest.mark.parametrize("reader", READERS)
@pytest.mark.slow
def test_fuzz_reader_fast(reader: str) -> None:
    census = _run(reader, 40)
    assert census.cases >= 40
    assert census.bad == 0, census.summary()


@pytest.mark.slow
@pytest.mark.parametrize("reader", READERS)
def test_fuzz_reader_many(reader: str) -> None:
    census = _run(reader, 600)
    assert census.cases >= 600
    assert census.bad == 0, census.summary()
