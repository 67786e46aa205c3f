"""Figure of a ZMP step sweep: measured vs expected ZMP of every target (paper A Fig. 14)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.analysis.figure import new_figure, save_figure

__all__ = ["ZmpStepCurve", "plot_zmp_steps"]

MM_PER_M = 1000.0


@dataclass(frozen=True)
class ZmpStepCurve:
    """One trial: measured (oscillating) and expected (step-form) ZMP on a common time axis.

    Attributes:
        label: legend text, e.g. ``"30 mm"``.
        time_s: time since the step [s], shape (N,).
        measured_m: measured ZMP [m], NaN where undefined, shape (N,).
        expected_m: expected ZMP of the command [m], shape (N,).
    """

    label: str
    time_s: NDArray[np.float64]
    measured_m: NDArray[np.float64]
    expected_m: NDArray[np.float64]


def plot_zmp_steps(
    curves: Sequence[ZmpStepCurve], path: str | Path, *, title: str, axis_label: str
) -> Path:
    """Plot every trial's measured ZMP (solid) and expected ZMP (dashed, same colour) in mm.

    Args:
        curves: the trials.
        path: PNG to write.
        title: figure title.
        axis_label: the ZMP coordinate, e.g. ``"ZMP x (forward)"``.
    """
    fig, ax = new_figure(width_in=9.0, height_in=5.5)
    colours = _colours(len(curves))
    for curve, colour in zip(curves, colours, strict=True):
        ax.plot(curve.time_s, MM_PER_M * curve.measured_m, color=colour, lw=1.0, label=curve.label)
        ax.plot(curve.time_s, MM_PER_M * curve.expected_m, color=colour, lw=1.0, ls="--")
    ax.plot([], [], color="0.3", lw=1.0, label="measured (F-T)")
    ax.plot([], [], color="0.3", lw=1.0, ls="--", label="expected (LIPM)")
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel("time since the step [s]")
    ax.set_ylabel(f"{axis_label} [mm]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), fontsize="small")
    return save_figure(fig, path)


def _colours(n: int) -> list[tuple[float, ...]]:
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    return [cmap(k / max(1, n - 1) * 0.9) for k in range(n)]
