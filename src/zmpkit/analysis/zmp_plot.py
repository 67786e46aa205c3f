"""Figure of a measured ZMP time series: both coordinates and the feet's normal forces."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.axes import Axes

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.sensors import ZmpSeries

__all__ = ["plot_zmp_series"]


def plot_zmp_series(series: ZmpSeries, path: str | Path, title: str = "Measured ZMP") -> Path:
    """Plot ZMP x/y [m] and both feet's world F_z [N] against time [s]; shade undefined spans."""
    fig, axes = new_figure(2, 1, width_in=9.0, height_in=6.0)
    ax_zmp, ax_fz = axes[0, 0], axes[1, 0]
    ax_zmp.plot(series.time, series.zmp[:, 0], label="zmp_x (forward)")
    ax_zmp.plot(series.time, series.zmp[:, 1], label="zmp_y (left)")
    _shade_undefined(ax_zmp, series.time, ~series.defined)
    ax_zmp.set_ylabel("ZMP in world [m]")
    ax_zmp.set_title(title)
    ax_zmp.legend(loc="best")
    ax_zmp.grid(True, alpha=0.3)
    ax_fz.plot(series.time, series.fz_right, label="right F_z")
    ax_fz.plot(series.time, series.fz_left, label="left F_z")
    ax_fz.set_xlabel("time [s]")
    ax_fz.set_ylabel("normal force [N]")
    ax_fz.legend(loc="best")
    ax_fz.grid(True, alpha=0.3)
    return save_figure(fig, path)


def _shade_undefined(ax: Axes, time: np.ndarray, undefined: np.ndarray) -> None:
    if not undefined.any():
        return
    edges = np.flatnonzero(np.diff(np.r_[0, undefined.astype(np.int8), 0]))
    for k, (start, stop) in enumerate(zip(edges[::2], edges[1::2], strict=True)):
        t0, t1 = time[start], time[min(stop, len(time) - 1)]
        ax.axvspan(t0, t1, color="0.85", label="no contact: ZMP undefined" if k == 0 else None)
