r"""Metrics of a walk: trunk oscillation spectrum, measured ZMP, speed, feet distance and slip.

All functions take plain arrays (world frame x forward, y left, z up; one row per sample).

- Amplitude spectrum of a signal ``x_k`` sampled every ``dt``: detrended (linear fit removed),
  Hann-windowed ``w_k``, :math:`A(f) = 2 |X(f)| / \sum_k w_k`, so a sinusoid of amplitude
  ``a`` on a bin shows ``A = a``.
- ZMP of each foot from its F-T force ``F`` and moment ``τ`` about the sensor origin ``o``
  (both in the world frame; floor at z = 0): :math:`p_x = o_x - (τ_y + o_z F_x)/F_z`,
  :math:`p_y = o_y + (τ_x - o_z F_y)/F_z`; feet in contact combine weighted by ``F_z``.
- A foot is in contact while its ``F_z`` is at least :data:`CONTACT_FORCE_N`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = [
    "CONTACT_FORCE_N",
    "MIN_PEAK_HZ",
    "FootSlip",
    "Spectrum",
    "amplitude_spectrum",
    "contact_phases",
    "double_support_distance",
    "fitted_speed",
    "foot_slip",
    "measured_zmp",
]

CONTACT_FORCE_N = 5.0
"""A foot is in contact while its vertical force is at least this [N] (~10 % of NAO's weight)."""
MIN_PEAK_HZ = 0.5
"""Spectral peaks are searched above this frequency [Hz] (below: drift, not oscillation)."""
MIN_CONTACT_SAMPLES = 5
"""A contact phase shorter than this many samples is a touch, not a stance [-]."""


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
    return Spectrum(np.fft.rfftfreq(x.size, dt_s), amplitude)


def measured_zmp(
    force_in_world: NDArray[np.float64],
    moment_in_world: NDArray[np.float64],
    sensor_in_world: NDArray[np.float64],
) -> NDArray[np.float64]:
    """ZMP on the floor z = 0 from the feet's F-T sensors [m], shape (N, 2); NaN without contact.

    Args:
        force_in_world: force of each foot [N], shape (N, F, 3).
        moment_in_world: moment about each sensor origin [N·m], shape (N, F, 3).
        sensor_in_world: sensor origins [m], shape (N, F, 3).
    """
    fx, fy, fz = (force_in_world[..., i] for i in range(3))
    tx, ty = moment_in_world[..., 0], moment_in_world[..., 1]
    ox, oy, oz = (sensor_in_world[..., i] for i in range(3))
    weight = np.where(fz >= CONTACT_FORCE_N, fz, 0.0)
    total = weight.sum(axis=1)
    num_x = np.sum(np.where(weight > 0, ox * fz - (ty + oz * fx), 0.0), axis=1)
    num_y = np.sum(np.where(weight > 0, oy * fz + (tx - oz * fy), 0.0), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        zmp = np.column_stack([num_x / total, num_y / total])
    zmp[total <= 0.0] = np.nan
    return zmp


def contact_phases(in_contact: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Runs of contact as (first, last) sample indices, shorter touches dropped."""
    flags = np.concatenate([[False], np.asarray(in_contact, bool), [False]])
    edges = np.flatnonzero(np.diff(flags.astype(int)))
    runs = zip(edges[::2], edges[1::2] - 1, strict=True)
    return [(int(a), int(b)) for a, b in runs if b - a + 1 >= MIN_CONTACT_SAMPLES]


def double_support_distance(
    sole_x_in_world: NDArray[np.float64], in_contact: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """Distance along x between two feet [m] while both touch the floor, NaN otherwise.

    Args:
        sole_x_in_world: sole-centre x of the two feet [m], shape (N, 2).
        in_contact: contact of the two feet, shape (N, 2).
    """
    both = np.all(in_contact, axis=1)
    return np.where(both, np.abs(sole_x_in_world[:, 0] - sole_x_in_world[:, 1]), np.nan)


@dataclass(frozen=True)
class FootSlip:
    """How far feet slide while they stand.

    Attributes:
        mean_abs_m: mean horizontal displacement of a sole over one stance phase [m].
        mean_x_m: mean x displacement over a stance phase; negative = backwards [m].
        phases: number of stance phases measured.
    """

    mean_abs_m: float
    mean_x_m: float
    phases: int


def foot_slip(
    sole_in_world: NDArray[np.float64], in_contact: NDArray[np.bool_], mask: NDArray[np.bool_]
) -> FootSlip:
    """Sole displacement over each stance phase that lies inside ``mask``.

    Args:
        sole_in_world: sole-centre positions [m], shape (N, F, 3).
        in_contact: contact flags, shape (N, F).
        mask: samples to consider (e.g. the steady walk), shape (N,).
    """
    moves = []
    for foot in range(sole_in_world.shape[1]):
        for a, b in contact_phases(in_contact[:, foot] & mask):
            moves.append(sole_in_world[b, foot, :2] - sole_in_world[a, foot, :2])
    if not moves:
        return FootSlip(0.0, 0.0, 0)
    d = np.array(moves)
    return FootSlip(float(np.mean(np.hypot(d[:, 0], d[:, 1]))), float(np.mean(d[:, 0])), len(d))


def fitted_speed(
    time_s: NDArray[np.float64], x_m: NDArray[np.float64], mask: NDArray[np.bool_]
) -> float:
    """Slope of a straight line fitted to ``x(t)`` over ``mask`` [m/s]."""
    if np.count_nonzero(mask) < 2:
        raise ParameterError("need at least two samples to fit a speed")
    return float(np.polyfit(time_s[mask], x_m[mask], 1)[0])
