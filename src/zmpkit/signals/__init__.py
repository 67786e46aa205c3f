"""zmpkit.signals: what is measured in a recorded signal, independent of how it was recorded.

- :mod:`~zmpkit.signals.step_metrics`: rise, settling, overshoot of a step response.
- :mod:`~zmpkit.signals.step_trial`: :class:`StepTrial`, one ZMP step as measured.
- :mod:`~zmpkit.signals.steady_state`: the settled window and value of a ZMP step
  (:func:`steady_state`).
- :mod:`~zmpkit.signals.spectra`: the amplitude spectrum of an oscillation.
- :mod:`~zmpkit.signals.contact_phases`: the feet's contact phases, step length, slip, speed.
"""

from __future__ import annotations

from zmpkit.signals.contact_phases import (
    FootSlip,
    contact_phases,
    double_support_distance,
    fitted_speed,
    foot_slip,
    in_contact,
)
from zmpkit.signals.robust_statistics import effective_sample_size
from zmpkit.signals.spectra import MIN_PEAK_HZ, Spectrum, amplitude_spectrum
from zmpkit.signals.steady_state import SteadyState, steady_state
from zmpkit.signals.step_metrics import StepMetrics, step_metrics
from zmpkit.signals.step_trial import PLANES, StepTrial

__all__ = [
    "MIN_PEAK_HZ",
    "PLANES",
    "FootSlip",
    "Spectrum",
    "SteadyState",
    "StepMetrics",
    "StepTrial",
    "amplitude_spectrum",
    "contact_phases",
    "double_support_distance",
    "effective_sample_size",
    "fitted_speed",
    "foot_slip",
    "in_contact",
    "steady_state",
    "step_metrics",
]
