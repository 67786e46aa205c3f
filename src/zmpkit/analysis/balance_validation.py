"""How well one controller put the measured ZMP on one target (paper A §4.6, Table 1).

For a step trial run under a controller (classic LIPM, scheduled DLIPM, or one linear
correction), the outcome holds the settled measured ZMP [m], the steady-state error
100·(measured − target)/target [%] (None at target 0), the overshoot [%] and 5 % settling
time [s] of the measured ZMP, and the RMS oscillation [m] about the settled value after the
response first reaches it. A trial that did not settle (the detector's creep check included,
:func:`zmpkit.signals.steady_state`) has none of these; it keeps its status, the drift rate
at its end [mm/s], its hold [s] and the error over its last second [%], so a report can say
"did not settle within H s (drift X mm/s)".

At small targets a percentage says little: the absolute error [mm] stands beside it
(:attr:`ControllerOutcome.error_mm`), and overshoot and settling time are measured only on
a step that stands out of the noise: the measured step (settled value − value before the
step) at least :data:`MIN_STEP_NOISE_RATIO` times the ZMP's sample-to-sample noise
(σ = 1.4826·MAD(Δy)/√2); a 3 mm target the robot barely moves to would otherwise read an
overshoot of thousands of percent of a step that is noise.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from zmpkit.signals import SteadyState, StepTrial, steady_state
from zmpkit.signals.robust_statistics import MAD_TO_SIGMA
from zmpkit.signals.step_metrics import step_metrics

__all__ = [
    "END_WINDOW_S",
    "MIN_STEP_NOISE_RATIO",
    "OUTCOME_STATUSES",
    "SETTLING_BAND",
    "ControllerOutcome",
    "evaluate_trial",
    "percent_error",
    "step_stands_out",
]

SETTLING_BAND = 0.05  # settling band, a fraction of the step size [-]
MIN_STEP_NOISE_RATIO = 5.0
"""Overshoot and settling are measured on steps at least this many noise σ tall [-]."""
END_WINDOW_S = 1.0
"""The end error is the mean over this last part of the record [s]."""
OUTCOME_STATUSES = ("settled", "drifting", "oscillating", "short", "tipping")
"""A trial's status: the detector's (:data:`zmpkit.signals.STATUSES`), or ended tipping."""


@dataclass(frozen=True, eq=False)
class ControllerOutcome:
    """One controller on one target.

    Attributes:
        controller: "lipm", "dlipm" or "linear".
        trial: the recorded trial (time [s], measured ZMP [m], target [m]).
        steady: the settled window and value of the measured ZMP.
        error_pct: 100·(measured − target)/target [%]; None at target 0 or if not settled.
        overshoot_pct: peak beyond the settled value, % of the step; None if undefined.
        settling_time_s: time after the step to stay within ±5 % of the step [s]; or None.
        rms_oscillation_m: RMS of (measured − settled value) after the first crossing of the
            settled value [m]; None if the response never reaches it.
        hold_end: how the trial's hold ended (:data:`zmpkit.experiments.hold.HOLD_ENDS`).
        hold_note: what the hold monitor saw; empty for a fixed hold.
    """

    controller: str
    trial: StepTrial
    steady: SteadyState
    error_pct: float | None
    overshoot_pct: float | None
    settling_time_s: float | None
    rms_oscillation_m: float | None
    hold_end: str = "hold"
    hold_note: str = ""

    @property
    def zmp_measured(self) -> float | None:
        """Settled measured ZMP [m], None if the trial did not settle."""
        return self.steady.value

    @property
    def error_mm(self) -> float | None:
        """Settled measured ZMP − target [mm]; None if the trial did not settle."""
        value = self.steady.value
        return None if value is None else 1e3 * (value - self.trial.zmp_ref)

    @property
    def status(self) -> str:
        """One of :data:`OUTCOME_STATUSES`: ``"tipping"`` if the hold ended so."""
        return "tipping" if self.hold_end == "tipping" else self.steady.status

    @property
    def hold_s(self) -> float:
        """Recorded time after the step [s]."""
        return float(self.trial.time[-1] - self.trial.t_step)

    @property
    def drift_mm_s(self) -> float | None:
        """Drift rate at the end of an unsettled trial [mm/s]; None if settled."""
        return None if self.steady.settled else self.steady.drift_rate_mm_s

    @property
    def end_error_pct(self) -> float | None:
        """Error of the mean over the last :data:`END_WINDOW_S` [%]; None at target 0."""
        t, y = self.trial.time, self.trial.zmp_measured
        return percent_error(float(np.mean(y[t >= t[-1] - END_WINDOW_S])), self.trial.zmp_ref)

    def unsettled_text(self) -> str:
        """``did not settle within H s (drift X mm/s)`` and why; empty if settled."""
        if self.steady.settled:
            return ""
        end = "" if self.end_error_pct is None else f", {self.end_error_pct:.1f} % at the end"
        if self.status == "tipping":
            return f"ended tipping after {self.hold_s:.1f} s{end}: {self.hold_note}"
        return (
            f"did not settle within {self.hold_s:.0f} s (drift {self.steady.drift_rate_mm_s:.3g} "
            f"mm/s, {self.status}{end})"
        )


def percent_error(measured: float | None, target: float) -> float | None:
    """100·(measured − target)/target [%]; None when undefined (target 0 or no value)."""
    if measured is None or target == 0.0:
        return None
    return 100.0 * (measured - target) / target


def evaluate_trial(
    controller: str, trial: StepTrial, hold_end: str = "hold", hold_note: str = ""
) -> ControllerOutcome:
    """Measure steady state, overshoot, settling and oscillation of one trial.

    Args:
        controller: "lipm", "dlipm" or "linear".
        trial: the recorded trial (time [s], measured ZMP [m], target [m]).
        hold_end: how its hold ended (:data:`zmpkit.experiments.hold.HOLD_ENDS`).
        hold_note: what the hold monitor saw.
    """
    steady = steady_state(trial)
    if hold_end == "tipping" and steady.settled:  # what it settled to is not a stance
        steady = replace(steady, value=None, std_error=None, settled=False, reason=hold_note)
    final = steady.value
    overshoot = settling = rms = None
    if final is not None and trial.zmp_ref != 0.0 and step_stands_out(trial, final):
        metrics = step_metrics(
            trial.time,
            trial.zmp_measured,
            t_step=trial.t_step,
            initial_value=_pre_step_value(trial),
            final_value=final,
            settling_band=SETTLING_BAND,
        )
        overshoot, settling = metrics.overshoot_pct, metrics.settling_time_s
        rms = _rms_after_first_crossing(trial, final)
    return ControllerOutcome(
        controller=controller,
        trial=trial,
        steady=steady,
        error_pct=percent_error(final, trial.zmp_ref),
        overshoot_pct=overshoot,
        settling_time_s=settling,
        rms_oscillation_m=rms,
        hold_end=hold_end,
        hold_note=hold_note,
    )


def step_stands_out(trial: StepTrial, final: float) -> bool:
    """Whether the measured step is at least :data:`MIN_STEP_NOISE_RATIO` noise σ tall."""
    noise = MAD_TO_SIGMA * float(np.median(np.abs(np.diff(trial.zmp_measured)))) / np.sqrt(2.0)
    return abs(final - _pre_step_value(trial)) >= MIN_STEP_NOISE_RATIO * noise


def _pre_step_value(trial: StepTrial) -> float:
    before = trial.time < trial.t_step
    return float(np.mean(trial.zmp_measured[before])) if before.any() else 0.0


def _rms_after_first_crossing(trial: StepTrial, final: float) -> float | None:
    after = trial.time >= trial.t_step
    deviation: NDArray[np.float64] = trial.zmp_measured[after] - final
    start = _pre_step_value(trial) - final
    crossed = np.flatnonzero(np.sign(deviation) != np.sign(start))
    if crossed.size == 0:
        return None
    tail = deviation[crossed[0] :]
    return float(np.sqrt(np.mean(tail**2)))
