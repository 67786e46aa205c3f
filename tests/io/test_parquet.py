"""Parquet F-T logs, the source dispatcher, units YAML, and garbage into the CSV reader."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers.ft_data import write_log
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io import (
    FT_LOG_COLUMNS,
    detect_source_kind,
    read_ft_log_csv,
    read_ft_log_parquet,
    read_ft_source,
    read_log_units,
)


def _rows(n: int = 5) -> np.ndarray:
    rows = np.arange(n * 13, dtype=float).reshape(n, 13) * 0.25 - 3.0
    rows[:, 0] = np.arange(n) * 0.01
    return rows


def write_parquet(path: Path, rows: np.ndarray, names: tuple[str, ...] = FT_LOG_COLUMNS) -> Path:
    table = pa.table({name: rows[:, i] for i, name in enumerate(names)})
    pq.write_table(table, path)
    return path


def test_round_trip_exact(tmp_path: Path) -> None:
    rows = _rows()
    log = read_ft_log_parquet(write_parquet(tmp_path / "log.parquet", rows))
    np.testing.assert_array_equal(log.time, rows[:, 0])
    np.testing.assert_array_equal(log.right_wrench, rows[:, 1:7])
    np.testing.assert_array_equal(log.left_wrench, rows[:, 7:13])


def test_column_map_yaml_through_the_dispatcher(tmp_path: Path) -> None:
    path = write_parquet(tmp_path / "log.pq", _rows(), ("t", *FT_LOG_COLUMNS[1:]))
    (tmp_path / "map.yaml").write_text("time: t\n")
    log = read_ft_source(path, column_map=tmp_path / "map.yaml")
    np.testing.assert_array_equal(log.time, _rows()[:, 0])


def test_integer_columns_are_read_as_floats(tmp_path: Path) -> None:
    table = pa.table(
        {name: pa.array(np.arange(3) + i, pa.int32()) for i, name in enumerate(FT_LOG_COLUMNS)}
    )
    pq.write_table(table, tmp_path / "log.parquet")
    log = read_ft_log_parquet(tmp_path / "log.parquet")
    np.testing.assert_array_equal(log.left_wrench[:, 5], np.arange(3) + 12.0)


def test_missing_mapped_column_same_text_as_csv(tmp_path: Path) -> None:
    path = write_parquet(tmp_path / "log.parquet", _rows())
    with pytest.raises(
        InputFileError, match=r"log.parquet: missing column 't' \(mapped from 'time'\); the file"
    ):
        read_ft_log_parquet(path, {"time": "t"})


def test_string_column(tmp_path: Path) -> None:
    data = {name: _rows()[:, i] for i, name in enumerate(FT_LOG_COLUMNS)}
    data["right_tx"] = ["1", "oops", "2", "3", "4"]
    pq.write_table(pa.table(data), tmp_path / "log.parquet")
    with pytest.raises(
        InputFileError, match=r"column 'right_tx': expected a number, got '1' \(column type string"
    ):
        read_ft_log_parquet(tmp_path / "log.parquet")


def test_null_and_nan_cells(tmp_path: Path) -> None:
    data = {name: pa.array(_rows()[:, i]) for i, name in enumerate(FT_LOG_COLUMNS)}
    data["left_fz"] = pa.array([1.0, None, 2.0, 3.0, 4.0])
    pq.write_table(pa.table(data), tmp_path / "null.parquet")
    with pytest.raises(
        InputFileError, match=r"column 'left_fz': row 2: expected a number, got null"
    ):
        read_ft_log_parquet(tmp_path / "null.parquet")
    rows = _rows()
    rows[3, 9] = np.nan
    path = write_parquet(tmp_path / "nan.parquet", rows)
    with pytest.raises(
        InputFileError, match=r"column 'left_fz': row 4: expected a finite number, got nan"
    ):
        read_ft_log_parquet(path)


def test_non_monotonic_time_and_empty(tmp_path: Path) -> None:
    rows = _rows()
    rows[3, 0] = rows[2, 0]
    path = write_parquet(tmp_path / "log.parquet", rows)
    with pytest.raises(
        InputFileError,
        match=r"column 'time': row 4: time must be strictly increasing, but 0.02 s follows 0.02 s",
    ):
        read_ft_log_parquet(path)
    empty = write_parquet(tmp_path / "empty.parquet", np.zeros((0, 13)))
    with pytest.raises(InputFileError, match=r"empty.parquet: no data rows"):
        read_ft_log_parquet(empty)


def test_not_parquet(tmp_path: Path) -> None:
    path = tmp_path / "log.parquet"
    path.write_bytes(b"PAR1 and then nothing useful")
    with pytest.raises(InputFileError, match=r"log.parquet: cannot be read as Parquet"):
        read_ft_log_parquet(path)


def test_dispatch_by_magic_and_suffix(tmp_path: Path) -> None:
    parquet = write_parquet(tmp_path / "log.data", _rows())
    csv = write_log(tmp_path / "log.csv", _rows())
    assert detect_source_kind(parquet) == "parquet"
    assert detect_source_kind(csv) == "csv"
    np.testing.assert_array_equal(
        read_ft_source(parquet).left_wrench, read_ft_source(csv).left_wrench
    )
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputFileError, match=r"empty: is a folder but neither a ROS 2 bag"):
        detect_source_kind(tmp_path / "empty")


def test_options_that_do_not_apply(tmp_path: Path) -> None:
    csv = write_log(tmp_path / "log.csv", _rows())
    with pytest.raises(ParameterError, match=r"right_topic applies to ROS 2 bags and YARP dumps"):
        read_ft_source(csv, right_topic="/ft/right")


def test_units_yaml_scales_flips_and_rotates(tmp_path: Path) -> None:
    rows = _rows()
    csv = write_log(tmp_path / "log.csv", rows)
    (tmp_path / "units.yaml").write_text(
        "right: {force_unit: daN, moment_unit: N·mm, signs: [1, -1, 1, 1, 1, -1]}\n"
        "left: {mounting_rpy: [0, 0, 3.141592653589793]}\n"
    )
    ft = read_ft_source(csv, units=tmp_path / "units.yaml")
    expected = rows[:, 1:7] * [10.0, -10.0, 10.0, 1e-3, 1e-3, -1e-3]
    np.testing.assert_array_equal(ft.right_wrench, expected)
    yaw_pi = rows[:, 7:13] * [-1.0, -1.0, 1.0, -1.0, -1.0, 1.0]
    np.testing.assert_allclose(ft.left_wrench, yaw_pi, rtol=0, atol=1e-12)


def test_units_yaml_errors(tmp_path: Path) -> None:
    path = tmp_path / "units.yaml"
    path.write_text("right: {moment_units: N·m}\n")
    with pytest.raises(InputFileError, match=r"unknown field 'right.moment_units'; valid: axis_"):
        read_log_units(path)
    path.write_text("right: {moment_unit: lbf·ft}\n")
    with pytest.raises(InputFileError, match=r"field 'right': unknown moment_unit 'lbf·ft'"):
        read_log_units(path)
    path.write_text("joint_angle_unit: grad\n")
    with pytest.raises(InputFileError, match=r"unknown joint_angle_unit 'grad'; valid: 'rad'"):
        read_log_units(path)


R = TypeVar("R")


def _outcome(read: Callable[[Path], R], path: Path) -> tuple[R | None, InputFileError | None]:
    """The reader's result, or the InputFileError it raised (any other exception escapes)."""
    try:
        return read(path), None
    except InputFileError as exc:
        return None, exc


_GARBAGE = settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@_GARBAGE
@given(data=st.binary(max_size=400))
def test_random_bytes_into_csv_reader(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "log.csv"
    path.write_bytes(data)
    with pytest.raises(InputFileError, match=r"log.csv"):
        read_ft_log_csv(path)  # random bytes never hold all 13 columns


@_GARBAGE
@given(
    lines=st.lists(
        st.lists(st.sampled_from(["0", "1.5", "-2", "nan", "x", "", "1e3", "inf"]), max_size=15),
        max_size=6,
    )
)
def test_random_rows_under_a_valid_header(tmp_path: Path, lines: list[list[str]]) -> None:
    path = tmp_path / "log.csv"
    path.write_text("\n".join([",".join(FT_LOG_COLUMNS), *(",".join(r) for r in lines)]) + "\n")
    log, exc = _outcome(read_ft_log_csv, path)
    if exc is not None:
        assert str(exc).startswith(str(path))
    else:
        assert np.all(np.isfinite(log.right_wrench))
        assert np.all(np.diff(log.time) > 0)
