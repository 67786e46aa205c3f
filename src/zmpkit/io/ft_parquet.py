"""Force–torque logs in Parquet: the columns and column map of :mod:`zmpkit.io.ft_log`.

Same canonical columns (:data:`~zmpkit.io.ft_log.FT_LOG_COLUMNS`, time in s, forces in N,
moments in N·m) and the same ``{canonical: name_in_file}`` column map as the CSV reader, and
the same error texts where they apply; a Parquet file has no lines, so rows are counted from
1 over the data and named in the message.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
from numpy.typing import NDArray

from zmpkit._validate import list_some, shorten
from zmpkit.errors import InputFileError
from zmpkit.io.ft_log import FT_LOG_COLUMNS, FtLog, column_names

__all__ = ["read_ft_log_parquet"]


def read_ft_log_parquet(path: str | Path, column_map: Mapping[str, str] | None = None) -> FtLog:
    """Read an F-T log Parquet file into an :class:`~zmpkit.io.ft_log.FtLog`.

    Args:
        path: the Parquet file.
        column_map: ``{canonical: column_in_file}`` for columns whose name differs.

    Raises:
        InputFileError: unreadable file, missing column, non-numeric column, null or
            non-finite value, no rows, or time not strictly increasing — naming the column
            and row.
    """
    path = Path(path)
    names = column_names(column_map, path)
    table = _read_table(path)
    _check_columns(path, table.column_names, names)
    values = np.column_stack(
        [_column(path, table.column(names[c]), names[c]) for c in FT_LOG_COLUMNS]
    )
    if values.shape[0] == 0:
        raise InputFileError(path, "no data rows; expected at least one sample")
    _check_time(path, values[:, 0], names["time"])
    return FtLog.from_columns(values, str(path))


def _read_table(path: Path) -> pa.Table:
    if not path.is_file():
        raise InputFileError(path, "file not found")
    try:
        return pq.read_table(path)
    except (pa.ArrowException, OSError, ValueError) as exc:
        raise InputFileError(path, f"cannot be read as Parquet ({exc})") from None


def _check_columns(path: Path, present: list[str], names: Mapping[str, str]) -> None:
    for canonical in FT_LOG_COLUMNS:
        wanted = names[canonical]
        if wanted not in present:
            renamed = f" (mapped from '{canonical}')" if wanted != canonical else ""
            raise InputFileError(
                path,
                f"missing column {shorten(wanted)}{renamed}; the file has: {list_some(present, 4)}",
            )
        if present.count(wanted) > 1:
            raise InputFileError(path, f"column '{wanted}' appears {present.count(wanted)} times")


def _column(path: Path, column: pa.ChunkedArray, name: str) -> NDArray[np.float64]:
    kind = column.type
    if not (pa.types.is_integer(kind) or pa.types.is_floating(kind)):
        first = next((v for v in column.to_pylist() if v is not None), None)
        raise InputFileError(
            path, f"expected a number, got {shorten(first)} (column type {kind})", column=name
        )
    if column.null_count:
        row = column.to_pylist().index(None) + 1
        raise InputFileError(path, f"row {row}: expected a number, got null", column=name)
    values = column.to_numpy().astype(np.float64)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        row = int(bad[0])
        raise InputFileError(
            path,
            f"row {row + 1}: expected a finite number, got {float(values[row])!r}",
            column=name,
        )
    return values


def _check_time(path: Path, time: NDArray[np.float64], column: str) -> None:
    bad = np.flatnonzero(np.diff(time) <= 0.0)
    if bad.size:
        k = int(bad[0]) + 1
        raise InputFileError(
            path,
            f"row {k + 1}: time must be strictly increasing, but {time[k]:g} s follows "
            f"{time[k - 1]:g} s",
            column=column,
        )
