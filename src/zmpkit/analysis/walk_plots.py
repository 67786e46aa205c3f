"""Figures of a walk, after paper B.

Trunk oscillation (Fig. 2), feet in contact (Fig. 3), feet distance in double support
(Fig. 4), oscillation per effect set (Fig. 6), target vs actual angle vs torque of a joint
(Figs. 7–9), and the trunk-pitch spectrum (Fig. 12).

Every function takes plain arrays, draws one figure and saves it as PNG.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.signals.spectra import Spectrum

__all__ = [
    "plot_effect_comparison",
    "plot_feet_distance",
    "plot_feet_in_contact",
    "plot_joint_tracking",
    "plot_trunk_pitch",
    "plot_trunk_spectrum",
]

Array = NDArray[np.float64]


def plot_trunk_pitch(time_s: Array, pitch_rad: Array, path: str | Path, title: str) -> Path:
    """Trunk pitch over time (paper B Fig. 2)."""
    fig, ax = new_figure()
    ax.plot(time_s, np.degrees(pitch_rad), lw=1.0)
    ax.set(xlabel="time [s]", ylabel="trunk pitch [deg]", title=title)
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_trunk_spectrum(
    spectrum: Spectrum, step_frequency_hz: float, path: str | Path, title: str
) -> Path:
    """Amplitude spectrum of the trunk pitch with the step frequency marked (Fig. 12)."""
    fig, ax = new_figure()
    keep = spectrum.frequency_hz <= 10.0
    ax.plot(spectrum.frequency_hz[keep], np.degrees(spectrum.amplitude[keep]), lw=1.0)
    ax.axvline(step_frequency_hz, color="grey", ls="--", lw=0.8, label="step frequency")
    ax.set(xlabel="frequency [Hz]", ylabel="amplitude [deg]", title=title)
    ax.legend()
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_feet_in_contact(
    time_s: Array,
    sole_x_m: Mapping[str, Array],
    in_contact: Mapping[str, NDArray[np.bool_]],
    path: str | Path,
    title: str,
) -> Path:
    """Sole x position of each foot, drawn only while it touches the floor (Fig. 3)."""
    fig, ax = new_figure()
    for foot, x in sole_x_m.items():
        contact = in_contact[foot]
        ax.plot(time_s[contact], x[contact], ".", ms=2, label=foot)
    ax.set(xlabel="time [s]", ylabel="sole x [m]", title=title)
    ax.legend()
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_feet_distance(
    time_s: Array, distance_m: Array, planned_m: float, path: str | Path, title: str
) -> Path:
    """Distance between the feet while both touch the floor (Fig. 4)."""
    fig, ax = new_figure()
    ax.plot(time_s, distance_m, ".", ms=2, label="measured")
    ax.axhline(planned_m, color="grey", ls="--", lw=0.8, label="planned step length")
    ax.set(xlabel="time [s]", ylabel="feet distance in double support [m]", title=title)
    ax.legend()
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_joint_tracking(
    time_s: Array,
    target_rad: Array,
    actual_rad: Array,
    torque_nm: Array,
    path: str | Path,
    title: str,
) -> Path:
    """Target and actual angle with the joint torque on a second axis (Figs. 7–9)."""
    fig, ax = new_figure()
    ax.plot(time_s, np.degrees(target_rad), lw=1.0, label="target angle")
    ax.plot(time_s, np.degrees(actual_rad), lw=1.0, label="actual angle")
    ax.set(xlabel="time [s]", ylabel="angle [deg]", title=title)
    twin = ax.twinx()
    twin.plot(time_s, torque_nm, color="tab:red", lw=0.8, alpha=0.7, label="torque")
    twin.set_ylabel("torque [N·m]")
    lines = ax.get_lines() + twin.get_lines()
    ax.legend(lines, [ln.get_label() for ln in lines], loc="upper right")
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_effect_comparison(
    runs: Mapping[str, tuple[Array, Array]], path: str | Path, title: str
) -> Path:
    """Trunk pitch over time for several effect sets, one row each (Fig. 6).

    Args:
        runs: effect-set label → (time [s], trunk pitch [rad]).
        path: the PNG file to write.
        title: the figure's title.

    Returns:
        The path of the saved figure.
    """
    fig, axes = new_figure(len(runs), 1, height_in=1.6 * len(runs) + 1.0)
    axes = np.atleast_1d(axes).ravel()
    limit = max(float(np.max(np.abs(np.degrees(p)))) for _, p in runs.values())
    for ax, (label, (time_s, pitch)) in zip(axes, runs.items(), strict=True):
        ax.plot(time_s, np.degrees(pitch), lw=0.8)
        ax.set_ylim(-limit, limit)
        ax.set_ylabel(f"{label}\n[deg]")
        ax.grid(True, alpha=0.3)
    axes[0].set_title(title)
    axes[-1].set_xlabel("time [s]")
    return save_figure(fig, path)
