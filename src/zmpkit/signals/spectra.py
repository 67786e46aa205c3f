r"""Amplitude spectra of sampled signals (paper B Fig. 6, 12: the trunk oscillation).

The amplitude spectrum of a signal ``x_k`` sampled every ``dt`` [s]: detrended (linear fit
removed), Hann-windowed ``w_k``,

.. math:: A(f) = \frac{2 |X(f)|}{\sum_k w_k},

so a sinusoid of amplitude ``a`` on a bin shows ``A = a`` (in the signal's unit).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = ["MIN_PEAK_HZ", "Spectrum", "amplitude_spectrum"]

MIN_PEAK_HZ = 0.5
"""Spectral peaks are searched above this frequency [Hz] (below: drift, not oscillation)."""


@dataclass(frozen=True)
class Spectrum:
    """One-sided amplitude spectrum.

    Attributes:
        frequency_hz: [Hz], shape (M,).
        amplitude: amplitude in the signal's unit, shape (M,).
    """

    frequency_hz: NDArray[np.float64]
    amplitude: NDArray[np.float64]

    def peak(self, min_hz: float = MIN_PEAK_HZ) -> tuple[float, float]:
        """Frequency [Hz] and amplitude of the largest bin above ``min_hz``."""
        band = self.frequency_hz >= min_hz
        if not np.any(band):
            raise ParameterError(f"the spectrum has no bin above {min_hz} Hz; use a longer signal")
        i = int(np.argmax(np.where(band, self.amplitude, -np.inf)))
        return float(self.frequency_hz[i]), float(self.amplitude[i])

    def at(self, frequency_hz: float) -> float:
        """Amplitude of the bin nearest ``frequency_hz``."""
        return float(self.amplitude[np.argmin(np.abs(self.frequency_hz - frequency_hz))])


def amplitude_spectrum(signal: NDArray[np.float64], dt_s: float) -> Spectrum:
    """Detrended, Hann-windowed one-sided amplitude spectrum (module docstring)."""
    x = np.asarray(signal, dtype=np.float64)
    if x.size < 8 or not np.all(np.isfinite(x)):
        raise ParameterError(f"need at least 8 finite samples for a spectrum, got {x.size}")
    t = np.arange(x.size)
    x = x - np.polyval(np.polyfit(t, x, 1), t)
    window = np.hanning(x.size)
    amplitude = 2.0 * np.abs(np.fft.rfft(x * window)) / window.sum()
    return Spectrum(np.asarray(np.fft.rfftfreq(x.size, dt_s), dtype=np.float64), amplitude)
