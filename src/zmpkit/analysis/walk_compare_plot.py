"""The rigid walk against the walk with effects on, overlaid (paper B Fig. 6).

Paper B's Fig. 6 shows the trunk oscillation of the same walk with each effect switched on;
this figure puts the walks of one command on shared axes: the trunk pitch over the same few
steps of their steady windows (left) and its amplitude spectrum over each walk's steady
window, the one of its ``summary.json`` (right). A walk that fell has no steady window: its
pitch is drawn up to the fall, which is marked, and it has no spectrum.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.signals.spectra import amplitude_spectrum

__all__ = ["WalkTrace", "plot_walk_comparison"]

Array = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class WalkTrace:
    """One walk's trunk pitch, for the comparison.

    Attributes:
        time_s: sample times [s], shape (N,).
        trunk_pitch_rad: IMU trunk pitch [rad], shape (N,).
        window_s: the summary's steady window [s].
        fall_time_s: when it fell [s], or None.
    """

    time_s: Array
    trunk_pitch_rad: Array
    window_s: tuple[float, float]
    fall_time_s: float | None = None


def plot_walk_comparison(
    walks: Mapping[str, WalkTrace],
    step_duration_s: float,
    path: str | Path,
    title: str,
    *,
    steps: int = 4,
) -> Path:
    """Overlay the trunk pitch [rad] and its spectrum [rad] of several walks.

    Args:
        walks: label → trace (e.g. ``rigid (effects off)``, ``all effects``).
        step_duration_s: duration of one step [s]; the step frequency is 1/step_duration_s.
        path: the PNG file to write.
        title: the figure's title.
        steps: steps shown in the time panel, from the latest start of the steady windows.
    """
    fig, axes = new_figure(1, 2, width_in=12.0, height_in=4.5)
    time_ax, spectrum_ax = axes[0, 0], axes[0, 1]
    standing = [w for w in walks.values() if w.fall_time_s is None]
    start = max((w.window_s[0] for w in standing), default=0.0)
    stop = start + steps * step_duration_s
    for k, (label, walk) in enumerate(walks.items()):
        colour = f"C{k}"
        t = walk.time_s
        shown = (t >= start) & (t <= stop)
        if walk.fall_time_s is not None:
            shown = t <= walk.fall_time_s
            time_ax.axvline(walk.fall_time_s, color=colour, ls=":", lw=1.5,
                            label=f"{label}: fell at {walk.fall_time_s:.2f} s")  # fmt: skip
        time_ax.plot(t[shown], walk.trunk_pitch_rad[shown], color=colour, lw=1.0, label=label)
        steady = (t >= walk.window_s[0]) & (t <= walk.window_s[1])
        if walk.fall_time_s is None and np.count_nonzero(steady) >= 8:
            spectrum = amplitude_spectrum(
                walk.trunk_pitch_rad[steady], float(np.median(np.diff(t)))
            )
            keep = spectrum.frequency_hz <= 10.0
            peak_hz, peak = spectrum.peak()
            peak_label = f"{label}: peak {peak:.4f} rad at {peak_hz:.2f} Hz"
            spectrum_ax.plot(spectrum.frequency_hz[keep], spectrum.amplitude[keep], color=colour,
                             lw=1.0, label=peak_label)  # fmt: skip
    spectrum_ax.axvline(1.0 / step_duration_s, color="grey", ls="--", lw=0.8,
                        label="step frequency")  # fmt: skip
    time_ax.set(xlabel="time [s]", ylabel="trunk pitch [rad]",
                title=f"{steps} steps of the steady walk")  # fmt: skip
    spectrum_ax.set(xlabel="frequency [Hz]", ylabel="amplitude [rad]",
                    title="spectrum over each steady window")  # fmt: skip
    for ax in (time_ax, spectrum_ax):
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small")
    fig.suptitle(title)
    return save_figure(fig, path)
