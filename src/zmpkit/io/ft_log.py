"""Force–torque logs in CSV: one row per sample, both feet's wrenches.

The canonical columns are :data:`FT_LOG_COLUMNS`::

    time, right_fx, right_fy, right_fz, right_tx, right_ty, right_tz,
          left_fx,  left_fy,  left_fz,  left_tx,  left_ty,  left_tz

time in s, forces in N, moments in N·m about the sensor origin, in each sensor's own frame.
A file with other header names is read through a column map (``{canonical: header}``),
see :func:`read_column_map`. Extra columns are ignored.
"""

from __future__ import annotations

import csv
import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import NoReturn

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError
from zmpkit.io.yaml_file import read_yaml_mapping

__all__ = ["FT_LOG_COLUMNS", "WRENCH_AXES", "FtLog", "read_column_map", "read_ft_log_csv"]

WRENCH_AXES = ("fx", "fy", "fz", "tx", "ty", "tz")
FT_LOG_COLUMNS: tuple[str, ...] = (
    "time",
    *(f"right_{a}" for a in WRENCH_AXES),
    *(f"left_{a}" for a in WRENCH_AXES),
)


@dataclass(frozen=True)
class FtLog:
    """Both feet's wrenches over time, in each sensor's frame.

    Attributes:
        time: sample times, strictly increasing [s], shape (N,).
        right_wrench: right foot (F_x, F_y, F_z, τ_x, τ_y, τ_z) [N, N·m], shape (N, 6).
        left_wrench: left foot, same layout, shape (N, 6).
        source: where the log came from.
    """

    time: NDArray[np.float64]
    right_wrench: NDArray[np.float64]
    left_wrench: NDArray[np.float64]
    source: str = ""

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return int(self.time.shape[0])


def read_column_map(path: str | Path) -> dict[str, str]:
    """Read a column-map YAML: ``canonical_name: header_in_file`` per line.

    Raises:
        InputFileError: an unknown canonical name (the valid ones are listed) or a non-string.
    """
    path = Path(path)
    data = read_yaml_mapping(path)
    mapping: dict[str, str] = {}
    for key, value in data.items():
        if key not in FT_LOG_COLUMNS:
            raise InputFileError(
                path, f"unknown column {key!r}; valid names: {', '.join(FT_LOG_COLUMNS)}"
            )
        if not isinstance(value, str) or not value:
            raise InputFileError(path, f"column {key!r} must map to a header name, got {value!r}")
        mapping[key] = value
    return mapping


def read_ft_log_csv(path: str | Path, column_map: Mapping[str, str] | None = None) -> FtLog:
    """Read an F-T log CSV into an :class:`FtLog`.

    Args:
        path: the CSV file, comma separated, one header line.
        column_map: ``{canonical: header}`` for columns whose header differs.

    Raises:
        InputFileError: empty file, missing column, short row, non-numeric or non-finite cell,
            or time not strictly increasing — naming the line and column.
    """
    path = Path(path)
    header = _read_header(path)
    names = {c: (column_map or {}).get(c, c) for c in FT_LOG_COLUMNS}
    index = _column_indices(path, header, names)
    values = _load_numeric(path, header, index, names)
    _check_time(path, values[:, 0], names["time"])
    return FtLog(
        time=values[:, 0].copy(),
        right_wrench=values[:, 1:7].copy(),
        left_wrench=values[:, 7:13].copy(),
        source=str(path),
    )


def _read_header(path: Path) -> list[str]:
    try:
        with path.open(newline="", encoding="utf-8") as f:
            first = next(csv.reader(f), None)
    except FileNotFoundError:
        raise InputFileError(path, "file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(path, f"cannot be read as UTF-8 text ({exc})") from None
    if not first or not any(cell.strip() for cell in first):
        raise InputFileError(
            path, f"empty file; expected a header line with columns {', '.join(FT_LOG_COLUMNS)}"
        )
    return [cell.strip() for cell in first]


def _column_indices(path: Path, header: list[str], names: Mapping[str, str]) -> list[int]:
    index = []
    for canonical in FT_LOG_COLUMNS:
        wanted = names[canonical]
        if wanted not in header:
            renamed = f" (mapped from '{canonical}')" if wanted != canonical else ""
            raise InputFileError(
                path,
                f"missing column '{wanted}'{renamed}; the header has: {', '.join(header)}",
                row=1,
            )
        index.append(header.index(wanted))
    return index


def _load_numeric(
    path: Path, header: list[str], index: list[int], names: Mapping[str, str]
) -> NDArray[np.float64]:
    """Parse the selected columns; on any problem, rescan row by row to name it exactly."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # "input contained no data"
            values = np.loadtxt(
                path,
                delimiter=",",
                skiprows=1,
                usecols=index,
                dtype=np.float64,
                ndmin=2,
                comments=None,
            )
    except (ValueError, IndexError):
        values = None
    if values is None or values.shape[1] != len(index) or not np.all(np.isfinite(values)):
        _raise_first_bad_cell(path, header, index)
    if values.shape[0] == 0:
        raise InputFileError(path, "no data rows after the header; expected at least one sample")
    return values


def _raise_first_bad_cell(path: Path, header: list[str], index: list[int]) -> NoReturn:
    with path.open(newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        next(reader)
        for line_no, row in enumerate(reader, start=2):
            if not row or not any(cell.strip() for cell in row):
                continue
            if len(row) < len(header):
                raise InputFileError(
                    path, f"row has {len(row)} cells, the header has {len(header)}", row=line_no
                )
            for i in index:
                _check_cell(path, line_no, header[i], row[i])
    raise InputFileError(path, "could not be parsed as numeric CSV")


def _check_cell(path: Path, line_no: int, column: str, cell: str) -> None:
    try:
        x = float(cell)
    except ValueError:
        raise InputFileError(
            path, f"expected a number, got {cell.strip()!r}", row=line_no, column=column
        ) from None
    if not math.isfinite(x):
        raise InputFileError(
            path, f"expected a finite number, got {cell.strip()!r}", row=line_no, column=column
        )


def _check_time(path: Path, time: NDArray[np.float64], column: str) -> None:
    steps = np.diff(time)
    bad = np.flatnonzero(steps <= 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        raise InputFileError(
            path,
            f"time must be strictly increasing, but {time[k]:g} s follows {time[k - 1]:g} s",
            row=k + 2,
            column=column,
        )
