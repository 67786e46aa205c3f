r"""The fit's cost: how far a simulated experiment is from the recorded one.

Up to four terms per experiment, each normalised by a scale taken from the recording itself
so they are dimensionless, comparable across robots and about 1 when the simulation misses
by as much as the signal varies:

- joint-angle error, against the recorded tracking error (the effects' footprint):

  .. math:: e_q = \frac{\operatorname{RMS}(q_{sim} - q_{rec})}
                        {\operatorname{RMS}(q_{rec} - q_{cmd})}

  over every sample and joint [rad/rad];
- ZMP error, both ZMPs through a centred moving mean of :data:`ZMP_SMOOTHING_S`
  (:math:`\mathcal{S}_p`), against the recorded one's variation about its linear trend (the
  walk's progress), over the samples where both ZMPs are defined, with the mean difference
  :math:`\bar d` removed (an F-T offset the user zeroes differently shifts the whole ZMP)
  unless the fit itself models the loads (``models_loads``: F-T offsets or the mass/CoM
  are fitted, and a CoM offset shows in nothing else as clearly):

  .. math:: e_p = \frac{\operatorname{RMS}\lVert \mathcal{S}_p(p_{sim}) - \mathcal{S}_p(p_{rec})
                        - \bar d\rVert}{\operatorname{RMS}\lVert \mathcal{S}_p(p_{rec}) -
                        \operatorname{trend}(\mathcal{S}_p(p_{rec}))\rVert};

  the F-T ZMP jumps from foot to foot at each touchdown, and a touchdown a tick earlier or
  later charged that jump in full on a row, which made the cost rough on small scales;

- only when the fit models the loads, the feet's vertical forces (right and left, world z,
  as the F-T sensors read them), each smoothed by a centred moving mean of
  :data:`FORCE_SMOOTHING_S` (:math:`\mathcal{S}`), against the robot's weight as its
  sensors read it, the recorded total's mean :math:`\bar W`:

  .. math:: e_f = \frac{\operatorname{RMS}\lVert \mathcal{S}(f_{sim}) - \mathcal{S}(f_{rec})
                        \rVert}{\bar W},\quad \bar W = \operatorname{mean}(f_{rec,r} + f_{rec,l}),

  over the samples where both are finite. A lifted foot reads its sensor's offset, and the
  total reads the weight, which the ZMP, a ratio of forces, hides; the smoothing keeps a
  touchdown a tick earlier or later from charging its load step as tens of newtons;
- trunk-oscillation spectrum distance: amplitude spectra of the IMU trunk tilt
  (:func:`~zmpkit.signals.spectra.amplitude_spectrum`) compared in
  :data:`SPECTRUM_BAND_HZ`:

  .. math:: e_s = \lVert A_{sim} - A_{rec} \rVert_2 / \lVert A_{rec} \rVert_2.

An experiment's cost is :math:`w_q e_q^2 + w_p e_p^2 + w_f e_f^2 + w_s e_s^2`; the fit
minimises their mean over experiments, the logs' windows entering by their median
(:mod:`~zmpkit.simfit.pooled_cost`). A rollout that falls or diverges before the recording
ends costs :data:`FAILED_COST` times (2 − the fraction it completed), so shorter falls cost more.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import uniform_filter1d

from zmpkit.signals.spectra import amplitude_spectrum
from zmpkit.simfit.recorded import RecordedSignals

__all__ = [
    "FAILED_COST",
    "FORCE_SMOOTHING_S",
    "SPECTRUM_BAND_HZ",
    "ZMP_SMOOTHING_S",
    "CostTerms",
    "CostWeights",
    "experiment_cost",
    "experiment_cost_of_parts",
    "force_rows",
    "load_scale_n",
    "smoothed_forces",
    "smoothed_zmp",
    "spectrum_in_band",
    "tracking_scale_rad",
    "zmp_miss",
    "zmp_spread_m",
]

SPECTRUM_BAND_HZ = (0.5, 8.0)
"""Band of the trunk-oscillation spectrum the cost compares [Hz]."""
FORCE_SMOOTHING_S = 0.2
r"""Width of the centred moving mean the feet's vertical forces are compared through [s]
(first zero at 5 Hz, −3 dB at about 2.2 Hz, 0.94 at a 0.5 s step's 1 Hz load transfer).
A touchdown one sample of ``dt`` later moves a load step ``ΔF`` by a sample; the mean
charges it :math:`ΔF \sqrt{dt / 0.2}` in RMS over the step instead of ``ΔF`` on one row."""
ZMP_SMOOTHING_S = 0.1
r"""Width of the centred moving mean both ZMPs are compared through [s] (first zero at
10 Hz, 0.94 of a 2 Hz sine kept). A touchdown one sample of ``dt`` later moves the ZMP's
jump to the new foot by a sample, which the mean charges :math:`\sqrt{dt / 0.1}` of the raw
miss. Chosen on the built-in walker's whole-catalogue self-test (seed 1's truth: the walks'
ZMP term's scatter under 0.5 % moves fell from 8.4e-5 to 1.5e-5, the ZMP term's most
concave curvature over ±10 % from -0.31 to -0.04); it takes some of what the walks' ZMP says
of the fastest effects (resolutions there with the others held: Coulomb friction 14 → 21 %,
gear damping 7.4 → 14 %)."""
FAILED_COST = 1000.0
"""Cost of a rollout that falls or diverges at its start [-]."""
_MIN_SCALE = 1e-6


@dataclass(frozen=True)
class CostWeights:
    """Weights of the cost terms [-].

    Attributes:
        joint: weight of :math:`e_q^2`.
        zmp: weight of :math:`e_p^2`.
        spectrum: weight of :math:`e_s^2`.
        force: weight of :math:`e_f^2` (charged only when the fit models the loads).
    """

    joint: float = 1.0
    zmp: float = 1.0
    spectrum: float = 1.0
    force: float = 1.0


@dataclass(frozen=True)
class CostTerms:
    """One experiment's normalised errors (module docstring) [-].

    Attributes:
        joint: :math:`e_q`.
        zmp: :math:`e_p`.
        spectrum: :math:`e_s`.
        completed: fraction of the recording the rollout reproduced [-].
        joint_rms_rad: the unnormalised joint-angle RMS error [rad].
        force: :math:`e_f` (0 when not charged or not recorded).
    """

    joint: float
    zmp: float
    spectrum: float
    completed: float
    joint_rms_rad: float
    force: float = 0.0

    def total(self, weights: CostWeights) -> float:
        """Weighted sum of squares, or the failure cost of an incomplete rollout [-]."""
        if self.completed < 1.0:
            return FAILED_COST * (2.0 - self.completed)
        return (
            weights.joint * self.joint**2
            + weights.zmp * self.zmp**2
            + weights.force * self.force**2
            + (weights.spectrum * self.spectrum**2)
        )


def _rms(x: NDArray[np.float64]) -> float:
    return float(np.sqrt(np.mean(np.square(x)))) if x.size else 0.0


def _detrended(t: NDArray[np.float64], x: NDArray[np.float64]) -> NDArray[np.float64]:
    return x - np.polyval(np.polyfit(t, x, 1), t)


def spectrum_in_band(signal: NDArray[np.float64], dt_s: float) -> tuple[NDArray, NDArray]:
    """Frequencies [Hz] and amplitudes [rad] of ``signal``'s spectrum in the cost band."""
    spectrum = amplitude_spectrum(signal, dt_s)
    lo, hi = SPECTRUM_BAND_HZ
    band = (spectrum.frequency_hz >= lo) & (spectrum.frequency_hz <= hi)
    return spectrum.frequency_hz[band], spectrum.amplitude[band]


def zmp_spread_m(time_s: NDArray[np.float64], zmp_m: NDArray[np.float64]) -> float:
    r"""The ZMP term's scale, at least 1e-6 [m].

    :math:`\operatorname{RMS}\lVert p - \operatorname{trend}(p)\rVert` over the rows given.
    """
    x, y = _detrended(time_s, zmp_m[:, 0]), _detrended(time_s, zmp_m[:, 1])
    spread = np.hypot(_rms(x), _rms(y))
    return max(float(spread), _MIN_SCALE)


def tracking_scale_rad(recorded: RecordedSignals) -> float:
    """The joint term's scale: the recorded tracking error's RMS, at least 1e-6 [rad]."""
    return max(_rms(recorded.q_meas_rad - recorded.q_cmd_rad), _MIN_SCALE)


def force_rows(rec: RecordedSignals, force_z_n: NDArray[np.float64]) -> NDArray[np.bool_]:
    """The rows where both the recorded and the simulated forces of both feet are finite."""
    sim = np.asarray(force_z_n, dtype=np.float64)
    return np.all(np.isfinite(rec.force_z_n), axis=1) & np.all(np.isfinite(sim), axis=1)


def _moving_mean(rows: NDArray[np.float64], dt_s: float, width_s: float) -> NDArray[np.float64]:
    """``rows`` through a centred moving mean of ``width_s``, its edges held."""
    width = max(1, round(width_s / dt_s))
    return np.asarray(uniform_filter1d(rows, width, axis=0, mode="nearest"))


def smoothed_forces(force_z_n: NDArray[np.float64], dt_s: float) -> NDArray[np.float64]:
    """``force_z_n`` ``(rows, feet)`` [N] through a moving mean of :data:`FORCE_SMOOTHING_S`.

    Centred, its edges held (the first and last rows repeated).
    """
    return _moving_mean(force_z_n, dt_s, FORCE_SMOOTHING_S)


def smoothed_zmp(zmp_m: NDArray[np.float64], dt_s: float) -> NDArray[np.float64]:
    """``zmp_m`` ``(rows, 2)`` [m] through a moving mean of :data:`ZMP_SMOOTHING_S`.

    Centred, its edges held; the rows given are taken as consecutive (the rows without a
    ZMP left out).
    """
    return _moving_mean(zmp_m, dt_s, ZMP_SMOOTHING_S)


def load_scale_n(force_z_n: NDArray[np.float64]) -> float:
    r"""The force term's scale :math:`\bar W`: the mean summed vertical force, at least 1e-6 [N]."""
    return max(float(np.mean(np.sum(force_z_n, axis=1))), _MIN_SCALE)


def _force_error(rec: RecordedSignals, force_z_n: NDArray[np.float64]) -> float:
    both = force_rows(rec, force_z_n)
    if np.count_nonzero(both) < 3:
        return 0.0
    recorded = rec.force_z_n[both]
    miss = smoothed_forces(np.asarray(force_z_n)[both], rec.dt_s) - smoothed_forces(
        recorded, rec.dt_s
    )
    return _rms(np.linalg.norm(miss, axis=1)) / load_scale_n(recorded)


def zmp_miss(
    rec: RecordedSignals,
    rows: NDArray[np.bool_],
    simulated_m: NDArray[np.float64],
    keep_mean: bool,
) -> tuple[NDArray[np.float64], float]:
    r"""The ZMP term's miss per row and its scale (module docstring).

    Args:
        rec: the recorded experiment.
        rows: the recorded rows compared (both ZMPs defined there).
        simulated_m: the simulated ZMP on those rows, ``(k, 2)`` [m].
        keep_mean: keep the mean difference :math:`\bar d` (the loads are modelled).

    Returns:
        :math:`\mathcal{S}_p(p_{sim}) - \mathcal{S}_p(p_{rec})`, less :math:`\bar d` unless
        kept, ``(k, 2)`` [m]; and the smoothed recording's spread about its trend [m].
    """
    p = smoothed_zmp(rec.zmp_m[rows], rec.dt_s)
    d = smoothed_zmp(simulated_m, rec.dt_s) - p
    return (d if keep_mean else d - d.mean(axis=0)), zmp_spread_m(rec.time_s[rows], p)


def _zmp_error(rec: RecordedSignals, zmp_m: NDArray[np.float64], keep_mean: bool) -> float:
    both = np.all(np.isfinite(rec.zmp_m), axis=1) & np.all(np.isfinite(zmp_m), axis=1)
    if np.count_nonzero(both) < 3:
        return 0.0
    miss, scale = zmp_miss(rec, both, np.asarray(zmp_m)[both], keep_mean)
    return _rms(np.linalg.norm(miss, axis=1)) / scale


def _spectrum_error(rec: RecordedSignals, trunk_tilt_rad: NDArray[np.float64]) -> float:
    _, a_rec = spectrum_in_band(rec.trunk_tilt_rad, rec.dt_s)
    _, a_sim = spectrum_in_band(trunk_tilt_rad, rec.dt_s)
    return float(np.linalg.norm(a_sim - a_rec) / max(float(np.linalg.norm(a_rec)), _MIN_SCALE))


def experiment_cost(
    recorded: RecordedSignals, simulated: RecordedSignals, models_loads: bool = False
) -> CostTerms:
    """The normalised errors of ``simulated`` against ``recorded`` (same time grid).

    Args:
        recorded: the recorded experiment's signals.
        simulated: the simulation's signals, on the recorded time grid.
        models_loads: the fit models the loads (F-T offsets or mass and CoM): charge the
            mean ZMP difference and the feet's vertical forces too (module docstring).
    """
    n = recorded.time_s.size
    if simulated.time_s.size < n:
        return _failed(simulated.time_s.size / n)
    square = float(np.sum(np.square(simulated.q_meas_rad - recorded.q_meas_rad)))
    return experiment_cost_of_parts(
        recorded,
        n,
        square,
        simulated.zmp_m,
        simulated.trunk_tilt_rad,
        simulated.force_z_n,
        models_loads,
    )


def _failed(completed: float) -> CostTerms:
    return CostTerms(np.inf, np.inf, np.inf, completed, np.inf, np.inf)


def experiment_cost_of_parts(
    recorded: RecordedSignals,
    rows: int,
    joint_square_sum: float,
    zmp_m: NDArray[np.float64],
    trunk_tilt_rad: NDArray[np.float64],
    force_z_n: NDArray[np.float64],
    models_loads: bool = False,
) -> CostTerms:
    r"""The normalised errors of a simulation given its joint term as a sum (a device's).

    Args:
        recorded: the recorded experiment's signals.
        rows: rows the simulation reproduced (fewer than recorded: a fall or divergence).
        joint_square_sum: :math:`\sum (q_{sim} - q_{rec})^2` over every row and joint
            [rad²] (unused unless every row was reproduced).
        zmp_m: the simulation's ZMP, world x and y, ``(rows, 2)`` [m]; NaN without contact.
        trunk_tilt_rad: the simulation's trunk tilt, ``(rows,)`` [rad].
        force_z_n: the simulation's vertical force of each foot, right then left,
            ``(rows, 2)`` [N].
        models_loads: charge the mean ZMP difference and the forces too (module docstring).
    """
    n = recorded.time_s.size
    completed = min(rows, n) / n
    if completed < 1.0:
        return _failed(completed)
    count = recorded.q_meas_rad.size
    q_err = float(np.sqrt(joint_square_sum / count)) if count else 0.0
    q_scale = tracking_scale_rad(recorded)
    spectrum = _spectrum_error(recorded, trunk_tilt_rad)
    zmp = _zmp_error(recorded, zmp_m, models_loads)
    force = _force_error(recorded, np.asarray(force_z_n)[:n]) if models_loads else 0.0
    return CostTerms(q_err / q_scale, zmp, spectrum, 1.0, q_err, force)
