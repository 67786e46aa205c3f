r"""The drift at the end of a step trial's record, for the steady-state detection.

The line through the last ``drift_window_s`` of a record gives its end drift rate and the
rate's standard error (from the effective sample size of its residuals); a settled window
whose end creeps beyond tolerance over the creep horizon is unsettled (step 5 of
:mod:`~zmpkit.signals.steady_state`), and an unsettled one is classified as drifting or
short by it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit._validate import in_range, positive
from zmpkit.signals.robust_statistics import effective_sample_size
from zmpkit.signals.steady_state_result import SteadyState, unsettled

__all__ = ["CreepCheck", "EndDrift", "classify_unsettled", "end_drift"]

_SIGNIFICANT_SLOPE_SE = 3.0  # a drift rate counts only beyond this many standard errors


@dataclass(frozen=True)
class EndDrift:
    """The line through the end of a record: slope [m/s], its standard error [m/s], span [s]."""

    slope: float
    std_error: float
    span_s: float
    residual_sigma: float

    @property
    def significant(self) -> bool:
        """Whether the slope lies beyond ``_SIGNIFICANT_SLOPE_SE`` standard errors."""
        return abs(self.slope) > _SIGNIFICANT_SLOPE_SE * self.std_error


def end_drift(times: NDArray[np.float64], values: NDArray[np.float64], window_s: float) -> EndDrift:
    r"""Least-squares line over the last ``window_s`` of ``(times, values)``.

    The slope's standard error uses the effective sample size of the residuals,
    :math:`SE = s\,\sqrt{n/n_{eff}} / \sqrt{\sum (t - \bar t)^2}`.
    """
    keep = times >= times[-1] - window_s
    t, y = times[keep], values[keep]
    if t.size < 3:
        return EndDrift(0.0, math.inf, 0.0, 0.0)
    slope, intercept = np.polyfit(t, y, 1)
    residual = y - (slope * t + intercept)
    n_eff = effective_sample_size(residual)
    spread = float(np.sum((t - t.mean()) ** 2))
    s = float(np.std(residual, ddof=2))
    se = s * math.sqrt(t.size / n_eff) / math.sqrt(spread)
    return EndDrift(float(slope), se, float(t[-1] - t[0]), s)


def classify_unsettled(
    result: SteadyState, end: EndDrift, band: float, window_s: float
) -> SteadyState:
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
        return unsettled(result, "drifting", reason, drift_rate=end.slope)
    return unsettled(result, "short", result.reason)


@dataclass(frozen=True)
class CreepCheck:
    """The creep check (module docstring, step 5)."""

    horizon_s: float
    fraction: float
    min_m: float

    @classmethod
    def checked(cls, horizon: float | None, fraction: float, min_m: float) -> CreepCheck | None:
        """The check of ``horizon`` [s], ``fraction`` [-] and ``min_m`` [m]; None: no check."""
        if horizon is None:
            return None
        return cls(
            positive("creep_horizon_s", horizon, "s"),
            in_range("creep_fraction", fraction, 0.0, 1.0),
            positive("creep_min_m", min_m, "m"),
        )

    def judge(self, result: SteadyState, end: EndDrift, step: float) -> SteadyState:
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
        return unsettled(result, "drifting", reason, drift_rate=end.slope)
