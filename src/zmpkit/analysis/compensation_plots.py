"""Figures of the walking compensation, after paper B.

The ZMP error per iteration of Algorithm 1 (Fig. 5), the measured ZMP against the modified
target (Figs. 10, 11), the trunk-pitch spectrum with and without each offset (Fig. 12) and a
box plot of the oscillation's standard deviation (Fig. 13).

Every function takes plain arrays, draws one figure and saves it as PNG.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.signals.spectra import Spectrum

__all__ = ["plot_iteration_rms", "plot_oscillation_boxes", "plot_spectra", "plot_zmp_target"]

Array = NDArray[np.float64]
MAX_FREQUENCY_HZ = 6.0
"""Upper end of the spectrum plot [Hz]."""


def plot_iteration_rms(rms_m: Sequence[float] | Array, path: str | Path, title: str) -> Path:
    """RMS of desired minus multibody ZMP per iteration of Algorithm 1 (Fig. 5) [mm]."""
    fig, ax = new_figure()
    iterations = np.arange(1, len(rms_m) + 1)
    ax.semilogy(iterations, 1e3 * np.asarray(rms_m), "o-")
    ax.axhline(1.0, color="grey", ls="--", lw=0.8, label="1 mm")
    ax.set(xlabel="iteration", ylabel="RMS ZMP error [mm]", title=title)
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    return save_figure(fig, path)


def plot_zmp_target(
    time_s: Array,
    desired_m: Array,
    target_m: Array,
    measured: Mapping[str, Array],
    path: str | Path,
    title: str,
) -> Path:
    """Walking-direction ZMP: desired, modified target and measured walks (Figs. 10, 11) [m].

    Args:
        time_s: [s], shape (N,).
        desired_m: the linear reference [m], shape (N,).
        target_m: the modified reference p' [m], shape (N,).
        measured: label -> measured ZMP x [m], shape (N,) (NaN without contact).
        path: the PNG file to write.
        title: the figure's title.

    Returns:
        The path of the saved figure.
    """
    fig, ax = new_figure()
    ax.plot(time_s, desired_m, color="grey", lw=1.0, ls="--", label="desired (linear)")
    ax.plot(time_s, target_m, lw=1.2, label="modified target")
    for label, zmp in measured.items():
        ax.plot(time_s[: len(zmp)], zmp, lw=0.8, alpha=0.8, label=f"measured, {label}")
    ax.set(xlabel="time [s]", ylabel="ZMP x [m]", title=title)
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_spectra(
    spectra: Mapping[str, Spectrum], step_frequency_hz: float, path: str | Path, title: str
) -> Path:
    """Trunk-pitch amplitude spectra, one line per walk (Fig. 12) [rad]."""
    fig, ax = new_figure()
    for label, spectrum in spectra.items():
        keep = spectrum.frequency_hz <= MAX_FREQUENCY_HZ
        ax.plot(spectrum.frequency_hz[keep], spectrum.amplitude[keep], lw=1.0, label=label)
    ax.axvline(step_frequency_hz, color="grey", ls="--", lw=0.8, label="step frequency")
    ax.set(xlabel="frequency [Hz]", ylabel="trunk pitch amplitude [rad]", title=title)
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)


def plot_oscillation_boxes(std_per_step: Mapping[str, Array], path: str | Path, title: str) -> Path:
    """Box plot of the trunk pitch's standard deviation over each step (Fig. 13) [rad]."""
    fig, ax = new_figure()
    labels = list(std_per_step)
    ax.boxplot([np.asarray(std_per_step[k]) for k in labels])
    ax.set_xticks(np.arange(1, len(labels) + 1), labels)
    ax.set(ylabel="trunk pitch std per step [rad]", title=title)
    ax.grid(True, axis="y", alpha=0.3)
    return save_figure(fig, path)
