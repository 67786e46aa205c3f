"""The settled value of a step response: the result of the steady-state detection.

What :func:`~zmpkit.signals.steady_state.steady_state` returns, settled or not.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

__all__ = ["STATUSES", "SteadyState", "unsettled"]

STATUSES = ("settled", "drifting", "oscillating", "short")
"""Values of :attr:`SteadyState.status`."""


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


def unsettled(
    result: SteadyState, status: str, reason: str, drift_rate: float | None = None
) -> SteadyState:
    """``result`` unsettled: no value, its ``status`` and ``reason``, its drift rate [m/s]."""
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
