r"""Step-response metrics: overshoot, peak, rise and settling time, steady-state error.

The response :math:`y(t)` of a step applied at :math:`t_{step}` goes from
:math:`y_0` (initial value) to :math:`y_\infty` (final value); with the step size
:math:`\Delta = y_\infty - y_0` (negative for a downward step) the metrics are

.. math::

    M_p = 100 \, \max\!\Big(0, \frac{\operatorname{sign}(\Delta)\,(y_{peak} - y_\infty)}
    {|\Delta|}\Big) \;[\%], \qquad
    t_s = \min\{t : |y(\tau) - y_\infty| \le b\,|\Delta| \;\forall \tau \ge t\} - t_{step}

Crossing times are linearly interpolated between samples. Times ``peak_time_s`` and
``settling_time_s`` are measured from :math:`t_{step}`. Quantities that the data leave
undefined are ``None``, never NaN.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite, finite_array, positive
from zmpkit.errors import ParameterError

__all__ = ["StepMetrics", "step_metrics"]

FloatArray = NDArray[np.float64]

FINAL_VALUE_FRACTION = 0.1
"""Fraction of the samples, at the end, whose mean is the default final value [-]."""


@dataclass(frozen=True)
class StepMetrics:
    r"""Metrics of one step response; units are those of the signal ([m] for a ZMP).

    Attributes:
        initial_value: :math:`y_0`, the value at the step time.
        final_value: :math:`y_\infty`, the steady-state value.
        step_size: :math:`y_\infty - y_0` (negative for a downward step).
        overshoot_pct: overshoot beyond :math:`y_\infty` in the step direction, in percent of
            :math:`|\Delta|` (0 when it never passes :math:`y_\infty`); None if the step is 0
            or too small for a finite percentage.
        peak_value: the sample farthest in the step direction (the farthest from
            :math:`y_0` if the step is 0).
        peak_time_s: time of ``peak_value`` after the step [s].
        rise_time_s: time from the lower to the upper rise limit [s]; None if the step is 0
            or the response never reaches the upper limit.
        settling_time_s: time after the step from which the response stays within
            ``settling_band`` · |step| of :math:`y_\infty` [s]; None if the step is 0 or
            the last sample is still outside the band.
        settling_band: half-width of the settling band, a fraction of |step| [-].
        rise_limits: lower and upper rise-time levels, fractions of the step [-].
        steady_state_error: reference − :math:`y_\infty`; None without a reference.
        steady_state_error_pct: 100 · error / reference [%] (positive when the response
            falls short of the reference); None when the reference is 0 or not given.
    """

    initial_value: float
    final_value: float
    step_size: float
    overshoot_pct: float | None
    peak_value: float
    peak_time_s: float
    rise_time_s: float | None
    settling_time_s: float | None
    settling_band: float
    rise_limits: tuple[float, float]
    steady_state_error: float | None
    steady_state_error_pct: float | None


def step_metrics(
    t: ArrayLike,
    y: ArrayLike,
    *,
    t_step: float = 0.0,
    initial_value: float | None = None,
    final_value: float | None = None,
    reference: float | None = None,
    settling_band: float = 0.02,
    rise_limits: tuple[float, float] = (0.1, 0.9),
    steady_window_s: float | None = None,
) -> StepMetrics:
    r"""Compute :class:`StepMetrics` of the sampled response ``y(t)``.

    Args:
        t: sample times [s], finite and strictly increasing, shape (N,), N >= 2.
        y: response samples, finite, shape (N,).
        t_step: time of the step [s], within ``[t[0], t[-1])``.
        initial_value: :math:`y_0`; default: ``y`` linearly interpolated at ``t_step``.
        final_value: :math:`y_\infty`; default: the mean of ``y`` over the last
            ``steady_window_s`` seconds, or, without it, over the last 10 % of the samples
            (at least one).
        reference: the commanded final value, for the steady-state error.
        settling_band: settling-band half-width as a fraction of |step|, in (0, 1).
        rise_limits: (lower, upper) fractions of the step, 0 <= lower < upper <= 1.
        steady_window_s: length of the final-value averaging window [s], > 0.

    Raises:
        ParameterError: naming the argument that is malformed or out of range.
    """
    times, values = _signal(t, y)
    t0 = _step_time(t_step, times)
    band, limits = _band_and_limits(settling_band, rise_limits)
    y0 = (
        float(np.interp(t0, times, values))
        if initial_value is None
        else finite("initial_value", initial_value)
    )
    y_inf = _final_value(times, values, final_value, steady_window_s)
    after = times >= t0
    ta, ya = times[after] - t0, values[after]
    step = y_inf - y0
    if not math.isfinite(step):
        raise ParameterError(f"the step {y_inf} - {y0} overflows the float range; rescale y")
    peak = _peak_index(ya, y0, step)
    error, error_pct = _steady_state_error(reference, y_inf)
    return StepMetrics(
        initial_value=y0,
        final_value=y_inf,
        step_size=step,
        overshoot_pct=_overshoot_pct(float(ya[peak]), y_inf, step),
        peak_value=float(ya[peak]),
        peak_time_s=float(ta[peak]),
        rise_time_s=_rise_time(ta, ya, y0, step, limits),
        settling_time_s=_settling_time(ta, ya, y_inf, step, band),
        settling_band=band,
        rise_limits=limits,
        steady_state_error=error,
        steady_state_error_pct=error_pct,
    )


def _signal(t: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray]:
    times, values = finite_array("t", t), finite_array("y", y)
    if times.ndim != 1 or values.ndim != 1:
        raise ParameterError(f"t and y must be 1-D, got shapes {times.shape} and {values.shape}")
    if times.size != values.size:
        raise ParameterError(
            f"t and y must have the same length, got {times.size} and {values.size}"
        )
    if times.size < 2:
        raise ParameterError(f"t and y need at least 2 samples, got {times.size}")
    steps = np.diff(times)
    if np.any(steps <= 0.0):
        k = int(np.argmax(steps <= 0.0))
        raise ParameterError(
            f"t must be strictly increasing, but t[{k + 1}] = {times[k + 1]} <= t[{k}] = {times[k]}"
        )
    return times, values


def _step_time(t_step: float, times: FloatArray) -> float:
    t0 = finite("t_step", t_step)
    if not times[0] <= t0 < times[-1]:
        raise ParameterError(
            f"t_step must lie in [t[0], t[-1]) = [{times[0]}, {times[-1]}) s, got {t0} s"
        )
    return t0


def _band_and_limits(band: float, limits: tuple[float, float]) -> tuple[float, tuple[float, float]]:
    b = finite("settling_band", band)
    if not 0.0 < b < 1.0:
        raise ParameterError(f"settling_band must lie in (0, 1) (a fraction of the step), got {b}")
    if len(limits) != 2:
        raise ParameterError(f"rise_limits must be (lower, upper), got {limits!r}")
    lo, hi = finite("rise_limits[0]", limits[0]), finite("rise_limits[1]", limits[1])
    if not 0.0 <= lo < hi <= 1.0:
        raise ParameterError(f"rise_limits must satisfy 0 <= lower < upper <= 1, got ({lo}, {hi})")
    return b, (lo, hi)


def _final_value(
    times: FloatArray, values: FloatArray, given: float | None, window_s: float | None
) -> float:
    if given is not None:
        return finite("final_value", given)
    if window_s is None:
        count = max(1, math.ceil(FINAL_VALUE_FRACTION * values.size))
        return float(np.mean(values[-count:]))
    in_window = times >= times[-1] - positive("steady_window_s", window_s, "s")
    return float(np.mean(values[in_window]))


def _peak_index(ya: FloatArray, y0: float, step: float) -> int:
    if step == 0.0:
        return int(np.argmax(np.abs(ya - y0)))
    return int(np.argmax(math.copysign(1.0, step) * ya))


def _overshoot_pct(peak: float, y_inf: float, step: float) -> float | None:
    """Overshoot in % of the step; None for a zero step or one whose percentage overflows."""
    if step == 0.0:
        return None
    with np.errstate(over="ignore"):
        value = 100.0 * math.copysign(1.0, step) * (peak - y_inf) / abs(step)
    return max(0.0, value) if math.isfinite(value) else None


def _first_crossing(ta: FloatArray, ya: FloatArray, target: float, sign: float) -> float | None:
    """First time ``ya`` reaches ``target`` going in direction ``sign`` (interpolated)."""
    reached = np.flatnonzero(sign * (ya - target) >= 0.0)
    if reached.size == 0:
        return None
    k = int(reached[0])
    if k == 0:
        return float(ta[0])
    frac = (target - ya[k - 1]) / (ya[k] - ya[k - 1])
    return float(ta[k - 1] + frac * (ta[k] - ta[k - 1]))


def _rise_time(
    ta: FloatArray, ya: FloatArray, y0: float, step: float, limits: tuple[float, float]
) -> float | None:
    if step == 0.0:
        return None
    sign = math.copysign(1.0, step)
    t_lo, t_hi = (_first_crossing(ta, ya, y0 + level * step, sign) for level in limits)
    if t_lo is None or t_hi is None:
        return None
    return t_hi - t_lo


def _settling_time(
    ta: FloatArray, ya: FloatArray, y_inf: float, step: float, band: float
) -> float | None:
    if step == 0.0:
        return None
    deviation = ya - y_inf
    half_width = band * abs(step)
    outside = np.flatnonzero(np.abs(deviation) > half_width)
    if outside.size == 0:
        return float(ta[0])
    j = int(outside[-1])
    if j == ya.size - 1:
        return None
    edge = math.copysign(half_width, deviation[j])
    frac = (deviation[j] - edge) / (deviation[j] - deviation[j + 1])
    return float(ta[j] + frac * (ta[j + 1] - ta[j]))


def _steady_state_error(reference: float | None, y_inf: float) -> tuple[float | None, float | None]:
    if reference is None:
        return None, None
    ref = finite("reference", reference)
    error = ref - y_inf
    return error, (None if ref == 0.0 else 100.0 * error / ref)
