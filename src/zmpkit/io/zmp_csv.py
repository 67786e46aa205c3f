"""Writing a ZMP time series as CSV: ``time, zmp_x, zmp_y, contact_right, contact_left``.

Where the ZMP is undefined (no foot in contact) the ``zmp_x`` and ``zmp_y`` cells are empty,
never a number; contacts are written as 0/1. A defined ZMP that is not finite is never
written: :func:`check_zmp_finite` refuses it, naming the row.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit.errors import NonFiniteResultError
from zmpkit.sensors import ZmpSeries

__all__ = ["ZMP_CSV_COLUMNS", "check_zmp_finite", "write_zmp_csv"]

ZMP_CSV_COLUMNS = ("time", "zmp_x", "zmp_y", "contact_right", "contact_left")


def check_zmp_finite(series: ZmpSeries, name: str = "zmp.csv") -> ZmpSeries:
    """Return ``series`` if its time and every defined ZMP are finite, else raise.

    Raises:
        NonFiniteResultError: naming ``name`` and the CSV row (header = row 1) of the first
            non-finite value.
    """
    bad = ~np.isfinite(series.time) | (series.defined & ~np.all(np.isfinite(series.zmp), axis=1))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        x, y = (float(v) for v in series.zmp[k])
        raise NonFiniteResultError(
            name, k + 2, f"the ZMP at t = {series.time[k]:g} s is ({x}, {y}) m, not finite"
        )
    return series


def write_zmp_csv(series: ZmpSeries, path: str | Path) -> Path:
    """Write ``series`` to ``path`` (time [s], ZMP in the world frame [m]) and return the path.

    Raises:
        NonFiniteResultError: before writing anything, if a value to write is not finite.
    """
    path = Path(path)
    check_zmp_finite(series, path.name)
    time = series.time.tolist()
    zx = series.zmp[:, 0].tolist()
    zy = series.zmp[:, 1].tolist()
    defined = series.defined.tolist()
    cr = series.contact_right.astype(int).tolist()
    cl = series.contact_left.astype(int).tolist()
    with path.open("w", encoding="utf-8", newline="") as f:
        f.write(",".join(ZMP_CSV_COLUMNS) + "\n")
        for t, x, y, ok, r, lt in zip(time, zx, zy, defined, cr, cl, strict=True):
            cells = f"{x!r},{y!r}" if ok else ","
            f.write(f"{t!r},{cells},{r},{lt}\n")
    return path
