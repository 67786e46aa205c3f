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
import re
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit._validate import list_some, shorten
from zmpkit.errors import InputFileError
from zmpkit.io.yaml_file import read_yaml_mapping
from zmpkit.sensors.mount import SensorMount
from zmpkit.sensors.plausibility import MAX_PLAUSIBLE_FORCE_N, MAX_PLAUSIBLE_MOMENT_NM
from zmpkit.sensors.zmp import ZmpSeries, zmp_series

__all__ = [
    "FT_LOG_COLUMNS",
    "MAX_PLAUSIBLE_FORCE_N",
    "MAX_PLAUSIBLE_MOMENT_NM",
    "WRENCH_AXES",
    "FtLog",
    "check_plausible",
    "column_names",
    "read_column_map",
    "read_ft_log_csv",
]

WRENCH_AXES = ("fx", "fy", "fz", "tx", "ty", "tz")
FT_LOG_COLUMNS: tuple[str, ...] = (
    "time",
    *(f"right_{a}" for a in WRENCH_AXES),
    *(f"left_{a}" for a in WRENCH_AXES),
)
_ENCODING = "utf-8-sig"  # UTF-8, with or without the byte-order mark spreadsheets write
_NUMBER = re.compile(r"^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$")
_NON_FINITE = re.compile(r"^[+-]?(nan|inf|infinity)$", re.IGNORECASE)


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

    @classmethod
    def from_columns(cls, values: NDArray[np.float64], source: str) -> FtLog:
        """A log from its columns, time then the right and left wrenches, copied.

        Args:
            values: time [s], right (F_x … τ_z), left (F_x … τ_z) [N, N·m], shape (N, 13).
            source: where the log came from.
        """
        return cls(
            time=values[:, 0].copy(),
            right_wrench=values[:, 1:7].copy(),
            left_wrench=values[:, 7:13].copy(),
            source=source,
        )

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return int(self.time.shape[0])

    def zmp_series(
        self, mounts: Mapping[str, SensorMount], contact_threshold_n: float
    ) -> ZmpSeries:
        """The log's ZMP through the feet's sensor mounts (:func:`~zmpkit.sensors.zmp_series`).

        Args:
            mounts: ``{"right": ..., "left": ...}`` sensor mounts.
            contact_threshold_n: a foot is in contact above this world F_z [N].
        """
        return zmp_series(
            self.time,
            self.right_wrench,
            self.left_wrench,
            mounts["right"],
            mounts["left"],
            contact_threshold_n=contact_threshold_n,
        )


def check_plausible(log: FtLog) -> FtLog:
    """Return ``log`` if every force and moment lies within the plausible limits, else raise.

    The limits are :data:`MAX_PLAUSIBLE_FORCE_N` and :data:`MAX_PLAUSIBLE_MOMENT_NM`, on
    values in SI units (after any units file is applied).

    Raises:
        InputFileError: naming the log, the column, the sample (1-based) and its time.
    """
    for foot, wrench in (("right", log.right_wrench), ("left", log.left_wrench)):
        for j, axis in enumerate(WRENCH_AXES):
            force = j < 3
            limit = MAX_PLAUSIBLE_FORCE_N if force else MAX_PLAUSIBLE_MOMENT_NM
            bad = np.flatnonzero(~(np.abs(wrench[:, j]) <= limit))
            if bad.size:
                k, unit = int(bad[0]), "N" if force else "N·m"
                raise InputFileError(
                    log.source,
                    f"{wrench[k, j]:.4g} {unit} at sample {k + 1} (t = {log.time[k]:g} s) is "
                    f"beyond the plausible ±{limit:g} {unit} of a foot F-T sensor",
                    column=f"{foot}_{axis}",
                )
    return log


def read_column_map(path: str | Path) -> dict[str, str]:
    """Read a column-map YAML: ``canonical_name: header_in_file`` per line.

    Raises:
        InputFileError: an unknown canonical name (the valid ones are listed), a non-string,
            or two names sent to one header (naming both).
    """
    path = Path(path)
    data = read_yaml_mapping(path)
    mapping: dict[str, str] = {}
    for key, value in data.items():
        if key not in FT_LOG_COLUMNS:
            raise InputFileError(
                path,
                f"unknown column {shorten(key)}; valid names: {list_some(FT_LOG_COLUMNS, 4)}",
            )
        if not isinstance(value, str) or not value:
            raise InputFileError(
                path, f"column {key!r} must map to a header name, got {shorten(value)}"
            )
        mapping[key] = value
    column_names(mapping, path)
    return mapping


def column_names(column_map: Mapping[str, str] | None, source: str | Path) -> dict[str, str]:
    """The header name of every canonical column: ``column_map``'s, else its own.

    Raises:
        InputFileError: two canonical columns would read one header (naming ``source``,
            both columns and the header): the map is ambiguous.
    """
    names = {c: (column_map or {}).get(c, c) for c in FT_LOG_COLUMNS}
    seen: dict[str, str] = {}
    for canonical, header in names.items():
        if header in seen:
            raise InputFileError(
                source,
                f"ambiguous column map: both '{seen[header]}' and '{canonical}' read the "
                f"header {shorten(header)}; each column needs its own header",
            )
        seen[header] = canonical
    return names


def read_ft_log_csv(path: str | Path, column_map: Mapping[str, str] | None = None) -> FtLog:
    """Read an F-T log CSV into an :class:`FtLog`.

    The file may start with a UTF-8 byte-order mark (as spreadsheet programs write it) and
    may quote its cells (``"0.5"``).

    Args:
        path: the CSV file, comma separated, one header line.
        column_map: ``{canonical: header}`` for columns whose header differs.

    Raises:
        InputFileError: empty file, missing or duplicated column, ambiguous column map,
            short row, non-numeric or non-finite cell, or time not strictly increasing —
            naming the line and column.
    """
    path = Path(path)
    header = _read_header(path)
    names = column_names(column_map, path)
    index = _column_indices(path, header, names)
    values = _load_numeric(path, header, index)
    _check_time(path, values[:, 0], names["time"])
    return FtLog.from_columns(values, str(path))


def _read_header(path: Path) -> list[str]:
    try:
        with path.open(newline="", encoding=_ENCODING) as f:
            first = next(csv.reader(f), None)
    except FileNotFoundError:
        raise InputFileError(path, "file not found") from None
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputFileError(path, f"cannot be read as UTF-8 CSV text ({exc})") from None
    if not first or not any(cell.strip() for cell in first):
        raise InputFileError(
            path,
            f"empty file; expected a header line with columns {list_some(FT_LOG_COLUMNS, 4)}",
        )
    header = [cell.strip() for cell in first]
    _check_unique(path, header)
    return header


def _check_unique(path: Path, header: list[str]) -> None:
    seen: dict[str, int] = {}
    for k, name in enumerate(header, start=1):
        if name and name in seen:
            raise InputFileError(
                path,
                f"the header names {shorten(name)} twice (columns {seen[name]} and {k}); "
                "each column needs its own name",
                row=1,
            )
        seen[name] = k


def _column_indices(path: Path, header: list[str], names: Mapping[str, str]) -> list[int]:
    index = []
    for canonical in FT_LOG_COLUMNS:
        wanted = names[canonical]
        if wanted not in header:
            renamed = f" (mapped from '{canonical}')" if wanted != canonical else ""
            raise InputFileError(
                path,
                f"missing column {shorten(wanted)}{renamed}; the header has: "
                f"{list_some(header, 4)}",
                row=1,
            )
        index.append(header.index(wanted))
    return index


def _load_numeric(path: Path, header: list[str], index: list[int]) -> NDArray[np.float64]:
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
                quotechar='"',
                encoding=_ENCODING,
            )
    except (ValueError, IndexError, UnicodeDecodeError):
        values = None
    if values is None or values.shape[1] != len(index) or not np.all(np.isfinite(values)):
        values = _parse_rows(path, header, index)
    if values.shape[0] == 0:
        raise InputFileError(path, "no data rows after the header; expected at least one sample")
    return values


def _parse_rows(path: Path, header: list[str], index: list[int]) -> NDArray[np.float64]:
    """Parse row by row with the csv module; raise at the first bad row or cell."""
    rows: list[list[float]] = []
    try:
        with path.open(newline="", encoding=_ENCODING) as f:
            reader = csv.reader(f)
            next(reader)
            for line_no, row in enumerate(reader, start=2):
                if not row or not any(cell.strip() for cell in row):
                    continue
                if len(row) < len(header):
                    raise InputFileError(
                        path,
                        f"row has {len(row)} cells, the header has {len(header)}",
                        row=line_no,
                    )
                rows.append([_cell(path, line_no, header[i], row[i]) for i in index])
    except (UnicodeDecodeError, csv.Error) as exc:
        raise InputFileError(path, f"cannot be read as UTF-8 CSV text ({exc})") from None
    return np.array(rows, dtype=np.float64).reshape(len(rows), len(index))


def _cell(path: Path, line_no: int, column: str, cell: str) -> float:
    text = cell.strip()
    try:
        x = float(text) if _NUMBER.match(text) or _NON_FINITE.match(text) else None
    except ValueError:
        x = None
    if x is None:
        raise InputFileError(
            path, f"expected a number, got {shorten(text)}", row=line_no, column=column
        )
    if not math.isfinite(x):
        raise InputFileError(
            path, f"expected a finite number, got {shorten(text)}", row=line_no, column=column
        )
    return x


def _check_time(path: Path, time: NDArray[np.float64], column: str) -> None:
    steps = np.diff(time)
    bad = np.flatnonzero(~(steps > 0.0))
    if bad.size:
        k = int(bad[0]) + 1
        raise InputFileError(
            path,
            f"time must be strictly increasing, but {time[k]:g} s follows {time[k - 1]:g} s",
            row=k + 2,
            column=column,
        )
