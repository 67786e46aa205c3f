"""Figures of a walk, after paper B, in SI units.

Trunk pitch (Fig. 2) and roll, feet in contact (Fig. 3), feet distance in double support
(Fig. 4), oscillation per effect set (Fig. 6), target vs actual angle vs torque of a joint
(Figs. 7–9) with its tracking error, and the trunk-pitch spectrum (Fig. 12).

Every function takes plain arrays, draws one figure and saves it as PNG. Angles are in
[rad], as in ``summary.json``. Time plots shade the steady window the summary's metrics are
taken over and mark a fall (:class:`FallMark`) with its time and kind.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from numpy.typing import NDArray

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.signals.spectra import Spectrum

__all__ = [
    "FallMark",
    "PushMark",
    "plot_effect_comparison",
    "plot_feet_distance",
    "plot_feet_in_contact",
    "plot_joint_tracking",
    "plot_trunk_spectrum",
    "plot_trunk_tilt",
]

Array = NDArray[np.float64]
Window = tuple[float, float]

_FALL_COLOUR = "tab:red"


@dataclass(frozen=True)
class PushMark:
    """A push on the torso to mark on a time plot.

    Attributes:
        time_s: when it starts [s].
        duration_s: how long it lasts [s].
        label: what it was, e.g. ``push 20 N +y``.
    """

    time_s: float
    duration_s: float
    label: str


@dataclass(frozen=True)
class FallMark:
    """A fall to mark on a time plot.

    Attributes:
        time_s: when the walk was judged fallen [s].
        kind: how (``roll``, ``pitch``, ``height``, ``stall``).
    """

    time_s: float
    kind: str

    @property
    def label(self) -> str:
        """Legend text: ``fell (roll) at 6.32 s``."""
        return f"fell ({self.kind}) at {self.time_s:.2f} s"


def _decorate(
    ax: Axes,
    window_s: Window | None,
    fall: FallMark | None,
    pushes: Sequence[PushMark] = (),
) -> None:
    """Shade the steady window, mark pushes and the fall on a time axis."""
    if window_s is not None and window_s[1] > window_s[0]:
        ax.axvspan(*window_s, color="0.85", alpha=0.5, lw=0, label="steady window (metrics)")
    for push in pushes:
        ax.axvspan(push.time_s, push.time_s + push.duration_s, color="tab:orange", alpha=0.35,
                   lw=0, label=f"{push.label} at {push.time_s:.2f} s")  # fmt: skip
    if fall is not None:
        ax.axvline(fall.time_s, color=_FALL_COLOUR, lw=1.5, ls="-", label=fall.label)


def plot_trunk_tilt(
    time_s: Array,
    angle_rad: Array,
    path: str | Path,
    title: str,
    *,
    axis: str = "pitch",
    fall_tilt_rad: float | None = None,
    window_s: Window | None = None,
    fall: FallMark | None = None,
    pushes: Sequence[PushMark] = (),
) -> Path:
    """Trunk pitch (paper B Fig. 2) or roll [rad] over time, window shaded, fall marked.

    Falls of a sideways-swaying walk are roll falls: the roll grows step by step before it
    passes ``±fall_tilt_rad``, drawn dotted once the trace comes near it (earlier it would
    flatten the trace); the pitch figure alone does not show such a fall coming.

    Args:
        time_s: sample times [s].
        angle_rad: the IMU's pitch or roll [rad].
        path: the PNG file to write.
        title: the figure's title.
        axis: ``"pitch"`` or ``"roll"``.
        fall_tilt_rad: the tilt at which a walk counts as fallen [rad]; None: not drawn.
        window_s: the summary's steady window, shaded.
        fall: the fall to mark, if any.
        pushes: pushes to mark.
    """
    fig, ax = new_figure()
    ax.plot(time_s, angle_rad, lw=1.0, color="C0" if axis == "pitch" else "C2",
            label=f"trunk {axis} (IMU)")  # fmt: skip
    peak = float(np.nanmax(np.abs(angle_rad))) if np.size(angle_rad) else 0.0
    if fall_tilt_rad is not None and peak > 0.4 * fall_tilt_rad:
        for sign in (1.0, -1.0):
            ax.axhline(sign * fall_tilt_rad, color=_FALL_COLOUR, ls=":", lw=1.0,
                       label="fall tilt" if sign > 0 else "_nolegend_")  # fmt: skip
    _decorate(ax, window_s, fall, pushes)
    ax.set(xlabel="time [s]", ylabel=f"trunk {axis} [rad]", title=title)
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_trunk_spectrum(
    spectrum: Spectrum,
    step_frequency_hz: float,
    path: str | Path,
    title: str,
    *,
    window_s: Window | None = None,
) -> Path:
    """Amplitude spectrum [rad] of the trunk pitch, step frequency and peak marked (Fig. 12).

    The spectrum is the one of the summary (its steady ``window_s``), so its peak is the
    summary's ``trunk_pitch_peak_hz`` and ``trunk_pitch_peak_amplitude_rad``.
    """
    fig, ax = new_figure()
    keep = spectrum.frequency_hz <= 10.0
    ax.plot(spectrum.frequency_hz[keep], spectrum.amplitude[keep], lw=1.0, label="trunk pitch")
    ax.axvline(step_frequency_hz, color="grey", ls="--", lw=0.8, label="step frequency")
    peak_hz, peak = spectrum.peak()
    ax.plot([peak_hz], [peak], "v", color="C3", label=f"peak {peak:.4f} rad at {peak_hz:.2f} Hz")
    if window_s is not None:
        title = f"{title}\nsteady window {window_s[0]:.2f}–{window_s[1]:.2f} s"
    ax.set(xlabel="frequency [Hz]", ylabel="amplitude [rad]", title=title)
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_feet_in_contact(
    time_s: Array,
    sole_x_m: Mapping[str, Array],
    in_contact: Mapping[str, NDArray[np.bool_]],
    path: str | Path,
    title: str,
    *,
    fall: FallMark | None = None,
) -> Path:
    """Sole x position of each foot, drawn only while it touches the floor (Fig. 3)."""
    fig, ax = new_figure()
    for foot, x in sole_x_m.items():
        contact = in_contact[foot]
        ax.plot(time_s[contact], x[contact], ".", ms=2, label=foot)
    _decorate(ax, None, fall)
    ax.set(xlabel="time [s]", ylabel="sole x in world [m]", title=title)
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_feet_distance(
    time_s: Array,
    distance_m: Array,
    planned_m: Array,
    path: str | Path,
    title: str,
    *,
    window_s: Window | None = None,
    fall: FallMark | None = None,
    pushes: Sequence[PushMark] = (),
) -> Path:
    """Distance between the feet along the heading while both touch the floor (Fig. 4).

    Args:
        time_s: sample times [s].
        distance_m: measured distance along the walking heading [m]; NaN off double support.
        planned_m: the same distance of the planned feet [m] (the footstep plan as walked,
            shortened steps included); NaN off planned double support.
        path: the PNG file to write.
        title: the figure's title.
        window_s: the summary's steady window, shaded.
        fall: the fall to mark, if any.
        pushes: pushes to mark.
    """
    fig, ax = new_figure()
    ax.plot(time_s, planned_m, ".", ms=2, color="0.5", label="planned (footstep plan)")
    ax.plot(time_s, distance_m, ".", ms=2, color="C0", label="measured (soles)")
    _decorate(ax, window_s, fall, pushes)
    ax.set(xlabel="time [s]", ylabel="feet distance along heading [m]", title=title)
    ax.legend(loc="best", fontsize="small", markerscale=4)
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_joint_tracking(
    time_s: Array,
    target_rad: Array,
    actual_rad: Array,
    torque_nm: Array,
    path: str | Path,
    title: str,
    *,
    fall: FallMark | None = None,
) -> Path:
    """Target and actual angle with the torque, and the tracking error below (Figs. 7–9).

    Meant for a few steps (the caller picks the span): over a whole walk, errors of a few
    hundredths of a radian vanish in the line width. The lower panel is target − actual.
    """
    fig, axes = new_figure(2, 1, height_in=6.0)
    ax, err = axes[0, 0], axes[1, 0]
    ax.plot(time_s, target_rad, lw=1.2, label="target angle")
    ax.plot(time_s, actual_rad, lw=1.0, label="actual angle (encoder)")
    ax.set(ylabel="angle [rad]", title=title)
    twin = ax.twinx()
    twin.plot(time_s, torque_nm, color="tab:red", lw=0.8, alpha=0.6, label="torque")
    twin.set_ylabel("torque [N·m]")
    lines = ax.get_lines() + twin.get_lines()
    ax.legend(lines, [ln.get_label() for ln in lines], loc="upper right", fontsize="small")
    error = np.asarray(target_rad) - np.asarray(actual_rad)
    err.plot(time_s, error, color="C3", lw=1.0, label="target − actual")
    err.axhline(0.0, color="k", lw=0.6)
    _decorate(err, None, fall)
    err.set(xlabel="time [s]", ylabel="tracking error [rad]")
    err.legend(loc="upper right", fontsize="small")
    for a in (ax, err):
        a.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_effect_comparison(
    runs: Mapping[str, tuple[Array, Array]], path: str | Path, title: str
) -> Path:
    """Trunk pitch [rad] over time for several effect sets, one row each (Fig. 6).

    Args:
        runs: effect-set label → (time [s], trunk pitch [rad]).
        path: the PNG file to write.
        title: the figure's title.

    Returns:
        The path of the saved figure.
    """
    fig, axes = new_figure(len(runs), 1, height_in=1.6 * len(runs) + 1.0)
    axes = np.atleast_1d(axes).ravel()
    limit = max(float(np.max(np.abs(p))) for _, p in runs.values())
    for ax, (label, (time_s, pitch)) in zip(axes, runs.items(), strict=True):
        ax.plot(time_s, pitch, lw=0.8)
        ax.set_ylim(-limit, limit)
        ax.set_ylabel(f"{label}\n[rad]")
        ax.grid(True, alpha=0.3)
    axes[0].set_title(title)
    axes[-1].set_xlabel("time [s]")
    return save_figure(fig, path)
