"""How well a fitted simulator reproduces an experiment: trunk oscillation and joint angles.

For each experiment the recorded and the simulated trunk tilt are compared by the largest
peak of their amplitude spectra above :data:`~zmpkit.signals.spectra.MIN_PEAK_HZ`
(frequency [Hz] and amplitude [rad]), and the encoders by their RMS difference [rad].
Paper B's targets (issue 7): frequency within :data:`FREQUENCY_TOLERANCE_HZ`, amplitude
within :data:`AMPLITUDE_TOLERANCE` (relative).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from zmpkit.signals.spectra import amplitude_spectrum
from zmpkit.simfit.recorded import RecordedSignals

__all__ = [
    "AMPLITUDE_TOLERANCE",
    "FREQUENCY_TOLERANCE_HZ",
    "ReproductionCheck",
    "reproduction_check",
]

FREQUENCY_TOLERANCE_HZ = 0.1
"""Largest trunk-oscillation frequency difference that passes [Hz]."""
AMPLITUDE_TOLERANCE = 0.15
"""Largest relative trunk-oscillation amplitude difference that passes [-]."""


@dataclass(frozen=True)
class ReproductionCheck:
    """One experiment, recorded vs simulated.

    Attributes:
        experiment: its name.
        recorded_peak_hz: recorded trunk-oscillation frequency [Hz].
        simulated_peak_hz: simulated one [Hz].
        recorded_amplitude_rad: recorded amplitude at its peak [rad].
        simulated_amplitude_rad: simulated amplitude at its peak [rad].
        joint_rms_error_rad: RMS encoder difference over samples and joints [rad].
        resolution_hz: the spectra's bin width [Hz].
    """

    experiment: str
    recorded_peak_hz: float
    simulated_peak_hz: float
    recorded_amplitude_rad: float
    simulated_amplitude_rad: float
    joint_rms_error_rad: float
    resolution_hz: float

    @property
    def frequency_error_hz(self) -> float:
        """|simulated − recorded| peak frequency [Hz]."""
        return abs(self.simulated_peak_hz - self.recorded_peak_hz)

    @property
    def amplitude_error(self) -> float:
        """|simulated − recorded| / recorded amplitude [-]."""
        return abs(self.simulated_amplitude_rad / self.recorded_amplitude_rad - 1.0)

    @property
    def passed(self) -> bool:
        """Both within the targets."""
        return (
            self.frequency_error_hz <= FREQUENCY_TOLERANCE_HZ
            and self.amplitude_error <= AMPLITUDE_TOLERANCE
        )


def reproduction_check(
    name: str, recorded: RecordedSignals, simulated: RecordedSignals
) -> ReproductionCheck:
    """Compare a simulated experiment with its recording (NaN where the rollout fell short)."""
    dt = recorded.dt_s
    f_rec, a_rec = amplitude_spectrum(recorded.trunk_tilt_rad, dt).peak()
    resolution = 1.0 / (recorded.time_s.size * dt)
    if simulated.time_s.size < recorded.time_s.size:
        return ReproductionCheck(name, f_rec, math.nan, a_rec, math.nan, math.nan, resolution)
    f_sim, a_sim = amplitude_spectrum(simulated.trunk_tilt_rad, dt).peak()
    rms = float(np.sqrt(np.mean(np.square(simulated.q_meas_rad - recorded.q_meas_rad))))
    return ReproductionCheck(name, f_rec, f_sim, a_rec, a_sim, rms, resolution)
