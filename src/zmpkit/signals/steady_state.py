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

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import median_filter

from zmpkit._validate import in_range, positive
from zmpkit.errors import ParameterError
from zmpkit.signals.robust_statistics import effective_sample_size, robust_sigma
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


STATUSES = ("settled", "drifting", "oscillating", "short")
"""Values of :attr:`SteadyState.status`."""
CREEP_HORIZON_S = 10.0
"""Time ahead over which a creep at the end rate must stay within tolerance [s]."""
CREEP_TOLERANCE_FRACTION = 0.005
"""Creep tolerance over the horizon, a fraction of the step: 0.5 % [-]."""
CREEP_MIN_M = 2e-4
"""Smallest creep tolerance over the horizon, whatever the step: 0.2 mm [m]."""
DRIFT_WINDOW_S = 5.0
"""Length of the end of the record whose line gives the end drift rate [s]."""
_SIGNIFICANT_SLOPE_SE = 3.0  # a drift rate counts only beyond this many standard errors


@dataclass(frozen=True)
class SteadyState:
    """The settled value of a step response.

    Attributes:
        value: mean of the signal over the settled window [m]; None if not settled.
        std_error: its standard error, autocorrelation-corrected [m]; None if not settled.
        window: (start, end) of the settled window — or, if not settled, of the longest
            candidate — [s].
        n_samples: samples in ``window``.
        settled: whether a window meeting the minimum length and drift criteria exists.
        band: half-width of the band around the final median [m].
        noise_std: robust standard deviation of the last part about its trend [m].
        drift_rate: slope of a line fitted over the window [m/s]; for a ``"drifting"``
            signal, over the last ``drift_window_s`` of the record (the rate at its end).
        effective_samples: the effective sample size of the window [-].
        reason: why the signal is not settled; empty when it is.
        status: one of :data:`STATUSES` (module docstring).
    """

    value: float | None
    std_error: float | None
    window: tuple[float, float]
    n_samples: int
    settled: bool
    band: float
    noise_std: float
    drift_rate: float
    effective_samples: float
    reason: str = ""
    status: str = "settled"

    @property
    def drift_rate_mm_s(self) -> float:
        """:attr:`drift_rate` in [mm/s]."""
        return 1e3 * self.drift_rate


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
    fraction = in_range("tail_fraction", tail_fraction, 1e-6, 1.0)
    k_sigma = positive("band_sigmas", band_sigmas)
    step_fraction = in_range("band_step_fraction", band_step_fraction, 0.0, 1.0)
    floor = positive("min_band", min_band, "m")
    ratio = positive("max_noise_ratio", max_noise_ratio)
    limits = (positive("min_duration_s", min_duration_s, "s"), min_samples)
    creep = _Creep.checked(creep_horizon_s, creep_fraction, creep_min_m)
    drift_window = positive("drift_window_s", drift_window_s, "s")
    if min_samples < 3 or spike_samples < 1:
        raise ParameterError(
            f"min_samples must be >= 3 and spike_samples >= 1, got {min_samples} and "
            f"{spike_samples}"
        )
    after = trial.time >= trial.t_step
    times, values = trial.time[after], trial.zmp_measured[after]
    before = trial.zmp_measured[~after]
    y0 = float(np.median(before)) if before.size else float(values[0])
    n_tail = max(3, math.ceil(fraction * values.size))
    centre = float(np.median(values[-n_tail:]))
    sigma = robust_sigma(times[-n_tail:], values[-n_tail:])
    step_band = max(step_fraction * abs(centre - y0), floor)
    band = max(k_sigma * sigma, step_band)
    smooth = median_filter(values, size=spike_samples, mode="nearest")
    outside = np.flatnonzero(np.abs(smooth - centre) > band)
    start = min(int(outside[-1]) + 1, values.size - 1) if outside.size else 0
    result = _window_result(times[start:], values[start:], band, sigma, limits)
    if result.settled:
        start += _mser_truncation(values[start:])
        result = _window_result(times[start:], values[start:], band, sigma, limits)
    pre_step = _pre_step_sigma(trial, min_samples)
    noise = math.inf if pre_step is None else max(pre_step, floor / k_sigma)
    if result.settled and sigma > ratio * noise and k_sigma * sigma > step_band:
        reason = (
            f"the signal still fluctuates at the end (robust σ = {sigma:.3g} m, "
            f"{sigma / noise:.3g} times the pre-step noise, more than max_noise_ratio = "
            f"{ratio:g}, and ±{k_sigma:g}σ wider than the settling band ±{step_band:.3g} m): "
            "an oscillation that has not died out"
        )
        return _unsettled(result, "oscillating", reason)
    if not result.settled:
        return _classify(result, _end_drift(times, values, drift_window), band, drift_window)
    if creep is not None:
        inside = times >= result.window[0]
        end = _end_drift(times[inside], values[inside], drift_window)
        return creep.judge(result, end, abs(centre - y0))
    return result


@dataclass(frozen=True)
class _EndDrift:
    """The line through the end of a record: slope [m/s], its standard error [m/s], span [s]."""

    slope: float
    std_error: float
    span_s: float
    residual_sigma: float

    @property
    def significant(self) -> bool:
        return abs(self.slope) > _SIGNIFICANT_SLOPE_SE * self.std_error


def _end_drift(times: FloatArray, values: FloatArray, window_s: float) -> _EndDrift:
    r"""Least-squares line over the last ``window_s`` of ``(times, values)``.

    The slope's standard error uses the effective sample size of the residuals,
    :math:`SE = s\,\sqrt{n/n_{eff}} / \sqrt{\sum (t - \bar t)^2}`.
    """
    keep = times >= times[-1] - window_s
    t, y = times[keep], values[keep]
    if t.size < 3:
        return _EndDrift(0.0, math.inf, 0.0, 0.0)
    slope, intercept = np.polyfit(t, y, 1)
    residual = y - (slope * t + intercept)
    n_eff = effective_sample_size(residual)
    spread = float(np.sum((t - t.mean()) ** 2))
    s = float(np.std(residual, ddof=2))
    se = s * math.sqrt(t.size / n_eff) / math.sqrt(spread)
    return _EndDrift(float(slope), se, float(t[-1] - t[0]), s)


def _unsettled(
    result: SteadyState, status: str, reason: str, drift_rate: float | None = None
) -> SteadyState:
    rate = result.drift_rate if drift_rate is None else drift_rate
    return dataclasses.replace(
        result,
        value=None,
        std_error=None,
        settled=False,
        reason=reason,
        status=status,
        drift_rate=rate,
    )


def _classify(result: SteadyState, end: _EndDrift, band: float, window_s: float) -> SteadyState:
    """Status of an unsettled window: a creep or ramp (the end line explains it) or short."""
    moves = abs(end.slope) * end.span_s
    full = end.span_s >= 0.99 * window_s  # a shorter record may still be its transient
    if result.reason.startswith("the signal drifts") or (
        full and end.significant and moves > band and end.residual_sigma < 0.5 * moves
    ):
        reason = (
            f"{result.reason}; it drifts at {1e3 * end.slope:.3g} mm/s over the last "
            f"{end.span_s:.3g} s"
        )
        return _unsettled(result, "drifting", reason, drift_rate=end.slope)
    return _unsettled(result, "short", result.reason)


@dataclass(frozen=True)
class _Creep:
    """The creep check (module docstring, step 5)."""

    horizon_s: float
    fraction: float
    min_m: float

    @classmethod
    def checked(cls, horizon: float | None, fraction: float, min_m: float) -> _Creep | None:
        if horizon is None:
            return None
        return cls(
            positive("creep_horizon_s", horizon, "s"),
            in_range("creep_fraction", fraction, 0.0, 1.0),
            positive("creep_min_m", min_m, "m"),
        )

    def judge(self, result: SteadyState, end: _EndDrift, step: float) -> SteadyState:
        """Unsettle ``result`` [m] if its end creeps beyond tolerance over the horizon.

        Args:
            result: a settled window.
            end: the line through its end.
            step: the step's size [m].
        """
        tolerance = max(self.fraction * step, self.min_m)
        ahead = abs(end.slope) * self.horizon_s
        if not (end.significant and ahead > tolerance):
            return result
        reason = (
            f"the signal still creeps at {1e3 * end.slope:.3g} ± {1e3 * end.std_error:.3g} mm/s "
            f"over the last {end.span_s:.3g} s: {1e3 * ahead:.3g} mm in the next "
            f"{self.horizon_s:g} s, more than the creep tolerance {1e3 * tolerance:.3g} mm "
            f"(max({self.fraction:g} of the step, {1e3 * self.min_m:g} mm))"
        )
        return _unsettled(result, "drifting", reason, drift_rate=end.slope)


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
