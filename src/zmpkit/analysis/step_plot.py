"""Figures of angular step responses (paper A, Fig. 17 and 18)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.analysis.figure import new_figure, save_figure

__all__ = ["Curve", "plot_step_responses"]


@dataclass(frozen=True)
class Curve:
    """One labelled response: time [s] and angle [rad]."""

    label: str
    time_s: NDArray[np.float64]
    angle_rad: NDArray[np.float64]
    style: str = "-"


def plot_step_responses(
    curves: Sequence[Curve],
    path: str | Path,
    *,
    title: str,
    reference_rad: float | None = None,
    ylim_rad: tuple[float, float] | None = None,
) -> Path:
    """Plot ankle-angle step responses [rad] over time [s], with an optional dashed target.

    ``reference_rad`` is the LIPM's static angle asin(x/l) [rad], drawn dashed.
    """
    fig, ax = new_figure(width_in=8.0, height_in=4.5)
    for curve in curves:
        ax.plot(curve.time_s, curve.angle_rad, curve.style, label=curve.label)
    if reference_rad is not None:
        ax.axhline(reference_rad, color="0.4", ls="--", lw=1, label="LIPM static angle asin(x/l)")
    if ylim_rad is not None:
        ax.set_ylim(*ylim_rad)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("ankle angle θ [rad]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    return save_figure(fig, path)
