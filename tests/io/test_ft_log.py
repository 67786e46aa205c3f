"""Reading F-T log CSVs: values, column maps, and the exact error for each kind of bad file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from helpers.ft_data import write_log
from zmpkit.errors import InputFileError
from zmpkit.io import FT_LOG_COLUMNS, read_column_map, read_ft_log_csv


def _rows(n: int = 5) -> np.ndarray:
    rows = np.arange(n * 13, dtype=float).reshape(n, 13)
    rows[:, 0] = np.arange(n) * 0.01
    return rows


def test_reads_values_in_canonical_layout(tmp_path: Path) -> None:
    rows = _rows()
    log = read_ft_log_csv(write_log(tmp_path / "log.csv", rows))
    np.testing.assert_array_equal(log.time, rows[:, 0])
    np.testing.assert_array_equal(log.right_wrench, rows[:, 1:7])
    np.testing.assert_array_equal(log.left_wrench, rows[:, 7:13])
    assert log.n_samples == 5


def test_column_order_and_extra_columns_do_not_matter(tmp_path: Path) -> None:
    rows = _rows()
    header = ["extra", *reversed(FT_LOG_COLUMNS)]
    shuffled = np.column_stack([np.full(len(rows), 7.0), rows[:, ::-1]])
    log = read_ft_log_csv(write_log(tmp_path / "log.csv", shuffled, header))
    np.testing.assert_array_equal(log.right_wrench, rows[:, 1:7])


def test_column_map_renames(tmp_path: Path) -> None:
    header = ["t", *FT_LOG_COLUMNS[1:]]
    path = write_log(tmp_path / "log.csv", _rows(), header)
    (tmp_path / "map.yaml").write_text("time: t\n")
    log = read_ft_log_csv(path, read_column_map(tmp_path / "map.yaml"))
    assert log.time[1] == pytest.approx(0.01)


def test_unknown_name_in_column_map(tmp_path: Path) -> None:
    (tmp_path / "map.yaml").write_text("stamp: t\n")
    with pytest.raises(
        InputFileError, match=r"unknown column 'stamp'; valid names: time, right_fx"
    ):
        read_column_map(tmp_path / "map.yaml")


def test_missing_column(tmp_path: Path) -> None:
    path = write_log(tmp_path / "log.csv", _rows()[:, :-1], FT_LOG_COLUMNS[:-1])
    with pytest.raises(InputFileError, match=r"log.csv, line 1: missing column 'left_tz'"):
        read_ft_log_csv(path)


def test_mapped_column_missing_names_the_mapping(tmp_path: Path) -> None:
    path = write_log(tmp_path / "log.csv", _rows())
    with pytest.raises(InputFileError, match=r"missing column 't' \(mapped from 'time'\)"):
        read_ft_log_csv(path, {"time": "t"})


def test_non_numeric_cell(tmp_path: Path) -> None:
    rows = _rows().astype(object)
    rows[2, 4] = "oops"
    path = write_log(tmp_path / "log.csv", rows.tolist())
    with pytest.raises(
        InputFileError, match=r"line 4, column 'right_tx': expected a number, got 'oops'"
    ):
        read_ft_log_csv(path)


def test_nan_cell_is_an_error_not_a_silent_nan(tmp_path: Path) -> None:
    rows = _rows().astype(object)
    rows[1, 9] = "nan"
    path = write_log(tmp_path / "log.csv", rows.tolist())
    with pytest.raises(
        InputFileError, match=r"line 3, column 'left_fz': expected a finite number, got 'nan'"
    ):
        read_ft_log_csv(path)


def test_short_row(tmp_path: Path) -> None:
    path = write_log(tmp_path / "log.csv", _rows())
    text = path.read_text().splitlines()
    text[3] = ",".join(text[3].split(",")[:5])
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(InputFileError, match=r"line 4: row has 5 cells, the header has 13"):
        read_ft_log_csv(path)


def test_non_monotonic_time(tmp_path: Path) -> None:
    rows = _rows()
    rows[3, 0] = rows[2, 0]
    path = write_log(tmp_path / "log.csv", rows)
    with pytest.raises(
        InputFileError,
        match=r"line 5, column 'time': time must be strictly increasing, but 0.02 s follows 0.02 s",
    ):
        read_ft_log_csv(path)


def test_empty_file(tmp_path: Path) -> None:
    path = tmp_path / "log.csv"
    path.write_text("")
    with pytest.raises(InputFileError, match=r"log.csv: empty file; expected a header line"):
        read_ft_log_csv(path)


def test_header_only(tmp_path: Path) -> None:
    path = write_log(tmp_path / "log.csv", [])
    with pytest.raises(InputFileError, match=r"no data rows after the header"):
        read_ft_log_csv(path)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"nope.csv: file not found"):
        read_ft_log_csv(tmp_path / "nope.csv")
