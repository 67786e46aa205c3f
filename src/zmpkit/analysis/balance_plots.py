"""Figures of the balance validation (paper A Fig. 16, 20 and 21)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.analysis.table1 import Table1Row
from zmpkit.identify.params import PlaneIdentification

__all__ = ["plot_error_fit", "plot_step_responses_by_target", "plot_zmp_ref_vs_measured"]


def plot_error_fit(
    identification: PlaneIdentification,
    rows: Sequence[Table1Row],
    path: str | Path,
    *,
    plane: str,
) -> Path:
    """Fig. 16: steady-state measured ZMP against the commanded LIPM ZMP, with the fit [m].

    Every trial is drawn: the settled identification trials the error model was fitted on
    (filled), identification trials that did not settle and were left out of the fit (red
    ×, at the mean of their last second, with why), and the validation LIPM trials at
    targets the fit did not use (open squares: the LIPM commands x_cmd = ZMP_ref), which test
    the model on data it has not seen.
    """
    fit = identification.error_fit
    fig, axes = new_figure(1, 2, width_in=12.0, height_in=4.8)
    x_fit, y_fit = np.asarray(fit.x_cmd, dtype=float), np.asarray(fit.x_measured, dtype=float)
    unsettled = [
        (trial.x_cmd, _last_second_mean(trial.time, trial.zmp_measured))
        for trial, steady in zip(identification.trials, identification.steady_states, strict=True)
        if not steady.settled
    ]
    held_out = [
        (r.zmp_ref, r.lipm.zmp_measured)
        for r in rows
        if not r.fitted_on and r.lipm.zmp_measured is not None
    ]
    xs = [*x_fit, *(x for x, _ in unsettled), *(x for x, _ in held_out), 0.0]
    grid = np.linspace(min(xs), max(xs), 200)
    ax, res = axes[0, 0], axes[0, 1]
    ax.plot(grid, grid, "k--", lw=1, label="LIPM expectation (x_FT = x_cmd)")
    ax.plot(grid, fit.predict(grid), "C1", label=f"fitted error model ({fit.kind})")
    ax.plot(x_fit, y_fit, "o", color="C0", label="identification trials (fitted)")
    res.axhline(0.0, color="k", lw=1)
    res.plot(grid, 1e3 * (fit.predict(grid) - grid), "C1", label="fitted error")
    res.plot(x_fit, 1e3 * (y_fit - x_fit), "o", color="C0", label="fitted trials")
    if held_out:
        hx, hy = np.array(held_out, dtype=float).T
        label = "validation LIPM trials (not fitted)"
        ax.plot(hx, hy, "s", mfc="none", color="C2", label=label)
        res.plot(hx, 1e3 * (hy - hx), "s", mfc="none", color="C2", label=label)
    if unsettled:
        ux, uy = np.array(unsettled, dtype=float).T
        label = f"did not settle: left out of the fit ({len(unsettled)})"
        ax.plot(ux, uy, "x", color="C3", ms=8, label=label)
        res.plot(ux, 1e3 * (uy - ux), "x", color="C3", ms=8, label=label)
    ax.set(xlabel="commanded LIPM ZMP x_cmd [m]", ylabel="measured ZMP x_FT [m]")
    ax.set_title(f"Steady-state ZMP error model, {plane} (paper A Fig. 16)")
    res.set(xlabel="commanded LIPM ZMP x_cmd [m]", ylabel="x_FT − x_cmd [mm]")
    res.set_title("ZMP error against the LIPM")
    for a in (ax, res):
        a.legend(loc="best", fontsize="small")
        a.grid(True, alpha=0.3)
    return save_figure(fig, path)


def _last_second_mean(time_s: np.ndarray, zmp_m: np.ndarray) -> float:
    """Mean of the finite samples of the last second of a trial [m] (NaN if none)."""
    time_a, zmp_a = np.asarray(time_s), np.asarray(zmp_m)
    last = (time_a >= time_a[-1] - 1.0) & np.isfinite(zmp_a)
    return float(np.mean(zmp_a[last])) if np.any(last) else float("nan")


def plot_zmp_ref_vs_measured(rows: Sequence[Table1Row], path: str | Path, *, plane: str) -> Path:
    """Fig. 20: measured steady-state ZMP against its target for each controller [m].

    Targets outside the range the error model was fitted on are shaded: there the
    controllers extrapolated it. A trial that did not settle has no steady value: it is
    drawn as × at the mean of its last second, in its controller's colour.
    """
    fig, ax = new_figure(width_in=7.0, height_in=5.5)
    ref = np.array([r.zmp_ref for r in rows])
    _shade_extrapolated(ax, rows, ref)
    for name, style in (("lipm", "o-"), ("linear", "^-"), ("dlipm", "s-")):
        values = [getattr(r, name).zmp_measured for r in rows]
        y = np.array([np.nan if v is None else v for v in values])
        (line,) = ax.plot(ref, y, style, label=f"ZMP_{name.upper()}")
        unsettled = [
            (r.zmp_ref, _last_second_mean(o.trial.time, o.trial.zmp_measured))
            for r in rows
            if (o := getattr(r, name)).zmp_measured is None
        ]
        if unsettled:  # drawn, not dropped: where the trial ended, in the line's colour
            ux, uy = np.array(unsettled, dtype=float).T
            ax.plot(ux, uy, "x", color=line.get_color(), ms=9, mew=2,
                    label=f"{name.upper()}: did not settle (last second)")  # fmt: skip
    ax.plot(ref, ref, "k--", lw=1.2, zorder=5, label="ZMP_LIN (ideal)")  # on top: DLIPM hugs it
    ax.set(xlabel="ZMP_ref [m]", ylabel="measured ZMP_FT [m]")
    ax.set_title(f"ZMP comparison, {plane} (paper A Fig. 20)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    return save_figure(fig, path)


def _shade_extrapolated(ax: Axes, rows: Sequence[Table1Row], ref: np.ndarray) -> None:
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
    """Fig. 14/21: measured ZMP of every trial under LIPM and DLIPM; LIPM vs DLIPM at one target.

    One colour per target in the first two panels (the legend names it; the dashed line of
    the same colour is the target). A trial that did not settle ends in a red × with its
    status in the legend (``drifting``, ``tipping``, ...): it is drawn, not dropped.
    """
    fig, axes = new_figure(1, 3, width_in=16.0, height_in=5.0)
    for ax, name in zip(axes[0, :2], ("lipm", "dlipm"), strict=True):
        for k, row in enumerate(rows):
            outcome = getattr(row, name)
            trial = outcome.trial
            t = trial.time - trial.t_step
            colour = f"C{k % 10}"
            ax.plot(t, trial.zmp_measured, color=colour, lw=1, label=f"ZMP_ref {row.zmp_ref:g} m")
            ax.hlines(row.zmp_ref, 0.0, t[-1], colors=colour, linestyles="--", lw=0.8)
            status = outcome.steady.status
            if status != "settled":
                ax.plot(t[-1], trial.zmp_measured[-1], "x", color="C3", ms=9, mew=2,
                        label=f"{row.zmp_ref:g} m: {status}")  # fmt: skip
        ax.set_title(f"{name.upper()} step responses, {plane} (dashed: targets)")
        ax.set(xlabel="time after the step [s]", ylabel="measured ZMP [m]")
        ax.legend(loc="best", fontsize="x-small", ncol=2)
    chosen = min(rows, key=lambda r: abs(r.zmp_ref - compare_ref))
    cmp = axes[0, 2]
    for name in ("lipm", "dlipm"):
        trial = getattr(chosen, name).trial
        cmp.plot(trial.time - trial.t_step, trial.zmp_measured, label=name.upper())
    cmp.axhline(chosen.zmp_ref, color="k", ls="--", lw=1, label="ZMP_ref")
    cmp.set_title(f"LIPM vs DLIPM at {chosen.zmp_ref:g} m (paper A Fig. 21b)")
    cmp.set(xlabel="time after the step [s]", ylabel="measured ZMP [m]")
    cmp.legend(loc="best", fontsize="small")
    for a in axes.ravel():
        a.grid(True, alpha=0.3)
    return save_figure(fig, path)
