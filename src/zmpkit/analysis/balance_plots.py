"""Figures of the balance validation (paper A Fig. 16, 20 and 21)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.analysis.table1 import Table1Row
from zmpkit.identify import ErrorModelFit

__all__ = ["plot_error_fit", "plot_step_responses_by_target", "plot_zmp_ref_vs_measured"]


def plot_error_fit(
    x_cmd: ArrayLike,
    x_measured: ArrayLike,
    fitted_on: ArrayLike,
    fit: ErrorModelFit,
    path: str | Path,
    *,
    plane: str,
) -> Path:
    """Fig. 16: steady-state measured ZMP against the commanded LIPM ZMP, with the fit [m]."""
    fig, axes = new_figure(1, 2, width_in=11.0, height_in=4.5)
    x_cmd_a, x_meas_a, used = np.asarray(x_cmd), np.asarray(x_measured), np.asarray(fitted_on)
    grid = np.linspace(min(x_cmd_a.min(), 0.0), x_cmd_a.max(), 200)
    ax = axes[0, 0]
    ax.plot(grid, grid, "k--", lw=1, label="LIPM expectation (x_FT = x_cmd)")
    ax.plot(grid, fit.predict(grid), "C1", label=f"fit ({fit.kind})")
    ax.plot(x_cmd_a[used], x_meas_a[used], "o", color="C0", label="fitted targets")
    ax.plot(x_cmd_a[~used], x_meas_a[~used], "s", mfc="none", color="C2", label="validation")
    ax.set(xlabel="commanded LIPM ZMP x_cmd [m]", ylabel="measured ZMP x_FT [m]")
    ax.set_title(f"Steady-state ZMP error model, {plane} (paper A Fig. 16)")
    ax.legend(loc="best")
    res = axes[0, 1]
    res.axhline(0.0, color="k", lw=1)
    res.plot(x_cmd_a, 1e3 * (x_meas_a - x_cmd_a), "o", color="C0", label="x_FT − x_cmd")
    res.plot(grid, 1e3 * (fit.predict(grid) - grid), "C1", label="fitted error")
    res.set(xlabel="commanded LIPM ZMP x_cmd [m]", ylabel="error [mm]")
    res.set_title("ZMP error against the LIPM")
    res.legend(loc="best")
    for a in axes.ravel():
        a.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_zmp_ref_vs_measured(rows: Sequence[Table1Row], path: str | Path, *, plane: str) -> Path:
    """Fig. 20: measured steady-state ZMP against its target for each controller [m].

    Targets outside the range the error model was fitted on are shaded: there the
    controllers extrapolated it.
    """
    fig, ax = new_figure(width_in=7.0, height_in=5.5)
    ref = np.array([r.zmp_ref for r in rows])
    _shade_extrapolated(ax, rows, ref)
    for name, style in (("lipm", "o-"), ("linear", "^-"), ("dlipm", "s-")):
        values = [getattr(r, name).zmp_measured for r in rows]
        y = np.array([np.nan if v is None else v for v in values])  # plotted gaps only
        ax.plot(ref, y, style, label=f"ZMP_{name.upper()}")
    ax.plot(ref, ref, "k--", lw=1.2, zorder=5, label="ZMP_LIN (ideal)")  # on top: DLIPM hugs it
    ax.set(xlabel="ZMP_ref [m]", ylabel="measured ZMP_FT [m]")
    ax.set_title(f"ZMP comparison, {plane} (paper A Fig. 20)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    return save_figure(fig, path)


def _shade_extrapolated(ax, rows: Sequence[Table1Row], ref: np.ndarray) -> None:
    """Shade the targets beyond the fitted range on ``ax`` (x axis: targets [m])."""
    fit_range = next((r.fit_range_m for r in rows if r.fit_range_m is not None), None)
    if fit_range is None:
        return
    low, high = fit_range
    span = max(float(ref.max() - ref.min()), 1e-3)
    label = "outside the fitted range (extrapolated)"
    if ref.max() > high + 1e-6:
        ax.axvspan(high, float(ref.max()) + 0.05 * span, color="C3", alpha=0.12, label=label)
        label = "_nolegend_"
    if ref.min() < low - 1e-6:
        ax.axvspan(float(ref.min()) - 0.05 * span, low, color="C3", alpha=0.12, label=label)


def plot_step_responses_by_target(
    rows: Sequence[Table1Row], path: str | Path, *, plane: str, compare_ref: float = 0.09
) -> Path:
    """Fig. 14/21: measured ZMP of every trial under LIPM and DLIPM; LIPM vs DLIPM at one target."""
    fig, axes = new_figure(1, 3, width_in=15.0, height_in=4.5)
    for ax, name in zip(axes[0, :2], ("lipm", "dlipm"), strict=True):
        for k, row in enumerate(rows):
            trial = getattr(row, name).trial
            t = trial.time - trial.t_step
            ax.plot(t, trial.zmp_measured, color=f"C{k % 10}", lw=1)
            ax.hlines(row.zmp_ref, 0.0, t[-1], colors=f"C{k % 10}", linestyles="--", lw=0.8)
        ax.set_title(f"{name.upper()} step responses, {plane}")
        ax.set(xlabel="time after the step [s]", ylabel="measured ZMP [m]")
    chosen = min(rows, key=lambda r: abs(r.zmp_ref - compare_ref))
    cmp = axes[0, 2]
    for name in ("lipm", "dlipm"):
        trial = getattr(chosen, name).trial
        cmp.plot(trial.time - trial.t_step, trial.zmp_measured, label=name.upper())
    cmp.axhline(chosen.zmp_ref, color="k", ls="--", lw=1, label="ZMP_ref")
    cmp.set_title(f"LIPM vs DLIPM at {chosen.zmp_ref:.2f} m (paper A Fig. 21b)")
    cmp.set(xlabel="time after the step [s]", ylabel="measured ZMP [m]")
    cmp.legend(loc="best")
    for a in axes.ravel():
        a.grid(True, alpha=0.3)
    return save_figure(fig, path)
