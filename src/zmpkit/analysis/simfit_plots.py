"""Figures of a simulator fit: per-signal fit of each experiment, and the cost history.

Only drawing: the signals come in as arrays (:class:`~zmpkit.simfit.experiments.
RecordedSignals`), nothing is computed here beyond the spectrum shown.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from zmpkit.analysis.figure import new_figure, save_figure
from zmpkit.signals.spectra import amplitude_spectrum
from zmpkit.simfit.checkpoint import GenerationRecord
from zmpkit.simfit.recorded import RecordedSignals

__all__ = ["plot_cost_history", "plot_signal_fit"]


def _largest_tracking_error(signals: RecordedSignals) -> int:
    error = np.sqrt(np.mean(np.square(signals.q_meas_rad - signals.q_cmd_rad), axis=0))
    return int(np.argmax(error))


def plot_signal_fit(
    recorded: RecordedSignals, simulated: RecordedSignals, path: Path, title: str
) -> Path:
    """Plot recorded vs fitted simulation, save it to ``path`` and return the path.

    Panels: the joint with the largest tracking error [rad], ZMP x and y [m], trunk tilt
    [rad] and its amplitude spectrum [rad vs Hz].
    """
    fig, axes = new_figure(2, 2, width_in=11.0, height_in=7.0)
    n = min(recorded.time_s.size, simulated.time_s.size)
    t = recorded.time_s
    j = _largest_tracking_error(recorded)
    ax = axes[0, 0]
    ax.plot(t, recorded.q_cmd_rad[:, j], "k:", lw=1, label="commanded")
    ax.plot(t, recorded.q_meas_rad[:, j], lw=1.2, label="recorded")
    ax.plot(t[:n], simulated.q_meas_rad[:n, j], "--", lw=1.2, label="fitted sim")
    ax.set(xlabel="time [s]", ylabel=f"{recorded.joint_names[j]} [rad]")
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    for k, axis in enumerate("xy"):
        ax.plot(t, recorded.zmp_m[:, k], lw=1.0, label=f"ZMP {axis} recorded")
        ax.plot(t[:n], simulated.zmp_m[:n, k], "--", lw=1.0, label=f"ZMP {axis} fitted sim")
    ax.set(xlabel="time [s]", ylabel="ZMP [m]")
    ax.legend(fontsize=8)
    ax = axes[1, 0]
    ax.plot(t, recorded.trunk_tilt_rad, lw=1.2, label="recorded")
    ax.plot(t[:n], simulated.trunk_tilt_rad[:n], "--", lw=1.2, label="fitted sim")
    ax.set(xlabel="time [s]", ylabel="trunk tilt (IMU) [rad]")
    ax.legend(fontsize=8)
    ax = axes[1, 1]
    dt = recorded.dt_s
    for signals, style, label in ((recorded, "-", "recorded"), (simulated, "--", "fitted sim")):
        if signals.time_s.size >= 8:
            spectrum = amplitude_spectrum(signals.trunk_tilt_rad, dt)
            ax.plot(spectrum.frequency_hz, spectrum.amplitude, style, label=label)
    ax.set(xlabel="frequency [Hz]", ylabel="trunk tilt amplitude [rad]", xlim=(0.0, 8.0))
    ax.legend(fontsize=8)
    fig.suptitle(title)
    return save_figure(fig, path)


def plot_cost_history(history: Sequence[GenerationRecord], path: Path, title: str) -> Path:
    """Best-so-far, generation-best and median cost per generation (log scale) [-]."""
    fig, ax = new_figure()
    g = [r.generation for r in history]
    ax.semilogy(g, [r.best_so_far for r in history], "k-", lw=1.5, label="best so far")
    ax.semilogy(g, [r.best_cost for r in history], ".", label="generation best")
    ax.semilogy(g, [r.median_cost for r in history], ":", label="generation median")
    ax.set(xlabel="generation", ylabel="cost [-]", title=title)
    ax.legend()
    return save_figure(fig, path)
