"""Writing a ZMP time series as CSV: ``time, zmp_x, zmp_y, contact_right, contact_left``.

Where the ZMP is undefined (no foot in contact) the ``zmp_x`` and ``zmp_y`` cells are empty,
never a number; contacts are written as 0/1.
"""

from __future__ import annotations

from pathlib import Path

from zmpkit.sensors import ZmpSeries

__all__ = ["ZMP_CSV_COLUMNS", "write_zmp_csv"]

ZMP_CSV_COLUMNS = ("time", "zmp_x", "zmp_y", "contact_right", "contact_left")


def write_zmp_csv(series: ZmpSeries, path: str | Path) -> Path:
    """Write ``series`` to ``path`` (time [s], ZMP in the world frame [m]) and return the path."""
    path = Path(path)
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
