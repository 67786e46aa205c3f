r"""The steady-state value of a step trial's measured ZMP (paper A §4.1, Fig. 14).

A :class:`~zmpkit.signals.step_trial.StepTrial` is one push-recovery / ZMP-step experiment:
the ZMP measured by the ankle F-T sensors while the robot answers a step of its ZMP target at
:math:`t_{step}`.

:func:`steady_state` finds the settled window from the signal alone:

1. the last ``tail_fraction`` of the post-step samples sets a robust centre and spread,
   :math:`m = \operatorname{median}`, :math:`\hat\sigma = 1.4826\,\mathrm{MAD}` about its
   linear trend (so slow drift does not widen the band);
2. the band half-width is
   :math:`w = \max(k_\sigma \hat\sigma,\; f_\Delta |m - y_0|,\; w_{min})`;
3. the window starts after the last sample (of a short running median, which ignores
   isolated spikes) outside :math:`m \pm w` and ends at the last sample; the marginal
   standard error rule (MSER, :func:`_mser_truncation`) then trims from its start what is
   left of the transient inside the band, at most half of it;
4. it is *settled* if it lasts at least ``min_duration_s`` and ``min_samples`` and its
   linear trend moves less than :math:`w` across it (a ramp is not settled), and — when there
   are samples before the step — it does not still oscillate: not both
   :math:`\hat\sigma` above ``max_noise_ratio`` times their noise and
   :math:`k_\sigma\hat\sigma` above the settling band :math:`\max(f_\Delta|m - y_0|, w_{min})`;
5. and it does not *creep*: the slope :math:`\dot y_{end}` of a line through the last
   ``drift_window_s`` of the window, if significant (:math:`|\dot y_{end}| > 3\,SE`, its
   standard error from the effective sample size), must not move the signal by more than the
   creep tolerance within the creep horizon :math:`H`:

   .. math:: |\dot y_{end}|\,H \le \max(f_c |m - y_0|,\; c_{min})

   A creep too slow to be significant over ``drift_window_s`` of a noisy record passes:
   the check can only be as sharp as the record is long and quiet.
   A slow creep (a structure or a gear train yielding under a constant load) stays inside
   the band for seconds while the value it reads is still minutes from its end.

An unsettled signal is classified (:attr:`SteadyState.status`): ``"drifting"`` — a steady
creep or ramp, whose rate :attr:`SteadyState.drift_rate` is that of the last
``drift_window_s`` — ``"oscillating"`` (an oscillation that has not died out) or ``"short"``
(too little of the record inside the band, and neither of the two).

The value is the window mean; its standard error uses the effective sample size of the
autocorrelated residuals (:func:`~zmpkit.signals.robust_statistics.effective_sample_size`),
:math:`SE = s / \sqrt{n_{eff}}`, :math:`n_{eff} = n / (1 + 2\sum_k \rho_k)`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import median_filter

from zmpkit._validate import in_range, positive
from zmpkit.errors import ParameterError
from zmpkit.signals.end_drift import CreepCheck, classify_unsettled, end_drift
from zmpkit.signals.robust_statistics import effective_sample_size, robust_sigma
from zmpkit.signals.steady_state_result import STATUSES, SteadyState, unsettled
from zmpkit.signals.step_trial import StepTrial

__all__ = [
    "CREEP_HORIZON_S",
    "CREEP_MIN_M",
    "CREEP_TOLERANCE_FRACTION",
    "DRIFT_WINDOW_S",
    "STATUSES",
    "SteadyState",
    "steady_state",
]

FloatArray = NDArray[np.float64]


CREEP_HORIZON_S = 10.0
"""Time ahead over which a creep at the end rate must stay within tolerance [s]."""
CREEP_TOLERANCE_FRACTION = 0.005
"""Creep tolerance over the horizon, a fraction of the step: 0.5 % [-]."""
CREEP_MIN_M = 2e-4
"""Smallest creep tolerance over the horizon, whatever the step: 0.2 mm [m]."""
DRIFT_WINDOW_S = 5.0
"""Length of the end of the record whose line gives the end drift rate [s]."""


def _pre_step_sigma(trial: StepTrial, min_samples: int) -> float | None:
    """Robust noise of the samples before the step [m]; None if fewer than ``min_samples``."""
    before = trial.time < trial.t_step
    if np.count_nonzero(before) < min_samples:
        return None
    return robust_sigma(trial.time[before], trial.zmp_measured[before])


def steady_state(
    trial: StepTrial,
    *,
    tail_fraction: float = 0.2,
    band_sigmas: float = 4.0,
    band_step_fraction: float = 0.02,
    min_band: float = 1e-5,
    min_duration_s: float = 0.5,
    min_samples: int = 20,
    max_noise_ratio: float = 3.0,
    spike_samples: int = 5,
    creep_horizon_s: float | None = CREEP_HORIZON_S,
    creep_fraction: float = CREEP_TOLERANCE_FRACTION,
    creep_min_m: float = CREEP_MIN_M,
    drift_window_s: float = DRIFT_WINDOW_S,
) -> SteadyState:
    """Detect the settled window of ``trial.zmp_measured`` and estimate its value.

    Args:
        trial: the step trial.
        tail_fraction: fraction of the post-step samples, at the end, that sets the centre
            and spread, in (0, 1].
        band_sigmas: band half-width in robust standard deviations of the tail [-].
        band_step_fraction: smallest band half-width as a fraction of the step [-].
        min_band: smallest band half-width [m].
        min_duration_s: shortest settled window [s].
        min_samples: fewest samples in a settled window (and before the step for the noise
            check).
        max_noise_ratio: a tail whose spread exceeds this many times the pre-step noise
            (checked when there are ``min_samples`` samples before the step) and whose
            ±``band_sigmas`` σ is wider than the settling band (``band_step_fraction`` of the
            step, at least ``min_band``) is an oscillation that has not died out [-].
        spike_samples: length of the running median that ignores isolated spikes (1: none).
        creep_horizon_s: the creep horizon H [s]; None: no creep check (slow drift within
            the band is accepted).
        creep_fraction: creep tolerance over H as a fraction of the step [-].
        creep_min_m: smallest creep tolerance over H [m].
        drift_window_s: end of the record whose line gives the end drift rate [s].

    Returns:
        The :class:`SteadyState`; ``settled=False`` with a reason, a status and no value,
        when no window meets the criteria.
    """
    settings = _Settings.checked(
        tail_fraction, band_sigmas, band_step_fraction, min_band, min_duration_s, min_samples,
        max_noise_ratio, spike_samples, creep_horizon_s, creep_fraction, creep_min_m,
        drift_window_s,
    )  # fmt: skip
    after = trial.time >= trial.t_step
    times, values = trial.time[after], trial.zmp_measured[after]
    tail = _Tail.of(values, times, trial.zmp_measured[~after], settings)
    result = _settled_window(times, values, tail, spike_samples, settings.limits)
    pre_step = _pre_step_sigma(trial, min_samples)
    noise = math.inf if pre_step is None else max(pre_step, settings.floor / settings.k_sigma)
    return _judged(result, tail, times, values, noise, settings)


@dataclass(frozen=True)
class _Settings:
    """The checked settings of :func:`steady_state` (its Args, by its names)."""

    fraction: float
    k_sigma: float
    step_fraction: float
    floor: float
    ratio: float
    limits: tuple[float, int]
    creep: CreepCheck | None
    drift_window: float

    @classmethod
    def checked(
        cls,
        tail_fraction: float,
        band_sigmas: float,
        band_step_fraction: float,
        min_band: float,
        min_duration_s: float,
        min_samples: int,
        max_noise_ratio: float,
        spike_samples: int,
        creep_horizon_s: float | None,
        creep_fraction: float,
        creep_min_m: float,
        drift_window_s: float,
    ) -> _Settings:
        """The settings, checked; ParameterError naming the first out of range."""
        fraction = in_range("tail_fraction", tail_fraction, 1e-6, 1.0)
        k_sigma = positive("band_sigmas", band_sigmas)
        step_fraction = in_range("band_step_fraction", band_step_fraction, 0.0, 1.0)
        floor = positive("min_band", min_band, "m")
        ratio = positive("max_noise_ratio", max_noise_ratio)
        limits = (positive("min_duration_s", min_duration_s, "s"), min_samples)
        creep = CreepCheck.checked(creep_horizon_s, creep_fraction, creep_min_m)
        drift_window = positive("drift_window_s", drift_window_s, "s")
        if min_samples < 3 or spike_samples < 1:
            raise ParameterError(
                f"min_samples must be >= 3 and spike_samples >= 1, got {min_samples} and "
                f"{spike_samples}"
            )
        return cls(fraction, k_sigma, step_fraction, floor, ratio, limits, creep, drift_window)


def _judged(
    result: SteadyState,
    tail: _Tail,
    times: NDArray[np.float64],
    values: NDArray[np.float64],
    noise: float,
    settings: _Settings,
) -> SteadyState:
    """``result``, unless the tail still oscillates (beyond ``noise`` [m]) or creeps.

    An unsettled ``result`` is classified by the end's drift.
    """
    sigma, step_band = tail.sigma, tail.step_band
    ratio, k_sigma = settings.ratio, settings.k_sigma
    if result.settled and sigma > ratio * noise and k_sigma * sigma > step_band:
        reason = (
            f"the signal still fluctuates at the end (robust σ = {sigma:.3g} m, "
            f"{sigma / noise:.3g} times the pre-step noise, more than max_noise_ratio = "
            f"{ratio:g}, and ±{k_sigma:g}σ wider than the settling band ±{step_band:.3g} m): "
            "an oscillation that has not died out"
        )
        return unsettled(result, "oscillating", reason)
    window = settings.drift_window
    if not result.settled:
        return classify_unsettled(result, end_drift(times, values, window), tail.band, window)
    if settings.creep is not None:
        inside = times >= result.window[0]
        end = end_drift(times[inside], values[inside], window)
        return settings.creep.judge(result, end, abs(tail.centre - tail.y0))
    return result


@dataclass(frozen=True)
class _Tail:
    """What the end of the post-step record says: where it settles and how wide its band.

    Attributes:
        y0: the value before the step [m] (the pre-step median; the first post-step
            sample without one).
        centre: the median of the tail [m].
        sigma: the robust standard deviation of the tail [m].
        step_band: the smallest band half-width the step allows [m].
        band: the settling band's half-width [m].
    """

    y0: float
    centre: float
    sigma: float
    step_band: float
    band: float

    @classmethod
    def of(
        cls,
        values: NDArray[np.float64],
        times: NDArray[np.float64],
        before: NDArray[np.float64],
        settings: _Settings,
    ) -> _Tail:
        """The tail of the post-step ``values`` at ``times`` [s] (``before``: pre-step)."""
        fraction, k_sigma = settings.fraction, settings.k_sigma
        step_fraction, floor = settings.step_fraction, settings.floor
        y0 = float(np.median(before)) if before.size else float(values[0])
        n_tail = max(3, math.ceil(fraction * values.size))
        centre = float(np.median(values[-n_tail:]))
        sigma = robust_sigma(times[-n_tail:], values[-n_tail:])
        step_band = max(step_fraction * abs(centre - y0), floor)
        band = max(k_sigma * sigma, step_band)
        return cls(y0, centre, sigma, step_band, band)


def _settled_window(
    times: NDArray[np.float64],
    values: NDArray[np.float64],
    tail: _Tail,
    spike_samples: int,
    limits: tuple[float, int],
) -> SteadyState:
    """The window after the last (spike-filtered) sample outside the band, MSER-truncated."""
    smooth = median_filter(values, size=spike_samples, mode="nearest")
    outside = np.flatnonzero(np.abs(smooth - tail.centre) > tail.band)
    start = min(int(outside[-1]) + 1, values.size - 1) if outside.size else 0
    result = _window_result(times[start:], values[start:], tail.band, tail.sigma, limits)
    if result.settled:
        start += _mser_truncation(values[start:])
        result = _window_result(times[start:], values[start:], tail.band, tail.sigma, limits)
    return result


def _mser_truncation(y: FloatArray) -> int:
    r"""MSER: the first d <= n/2 samples to drop that minimise :math:`SS(d)/(n-d)^2`.

    :math:`SS(d)` is the sum of squares of :math:`y_{d..n-1}` about their mean; the rule
    (White 1997) trims what is left of a transient where it costs more variance than data.
    """
    z = y - y.mean()
    n = z.size
    s1 = np.cumsum(z[::-1])[::-1]
    s2 = np.cumsum((z * z)[::-1])[::-1]
    count = n - np.arange(n)
    half = n // 2 + 1
    criterion = (s2[:half] - s1[:half] ** 2 / count[:half]) / count[:half] ** 2
    return int(np.argmin(criterion))


def _window_result(
    t: FloatArray, y: FloatArray, band: float, sigma: float, limits: tuple[float, int]
) -> SteadyState:
    """Judge the candidate window ``(t, y)`` and estimate its mean and standard error."""
    min_duration, min_samples = limits
    n = t.size
    window = (float(t[0]), float(t[-1]))
    duration = window[1] - window[0]
    slope = float(np.polyfit(t, y, 1)[0]) if n >= 2 else 0.0
    n_eff = effective_sample_size(y)
    reason = ""
    if n < min_samples or duration < min_duration:
        reason = (
            f"the signal stays within ±{band:.3g} m of its final median for only "
            f"{duration:.3g} s and {n} samples (need {min_duration:.3g} s and {min_samples})"
        )
    elif abs(slope) * duration > band:
        reason = (
            f"the signal drifts {slope * duration:.3g} m across its window "
            f"({slope:.3g} m/s over {duration:.3g} s), more than the band ±{band:.3g} m"
        )
    if reason:
        return SteadyState(None, None, window, n, False, band, sigma, slope, n_eff, reason, "short")
    std = float(np.std(y, ddof=1))
    return SteadyState(
        float(np.mean(y)), std / math.sqrt(n_eff), window, n, True, band, sigma, slope, n_eff
    )
