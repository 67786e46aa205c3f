r"""Measured and expected ZMP of each trial, and the steady-state table (paper A Fig. 14, 16).

Per trial, from the dataset alone (sensors + design knowledge in ``meta.json``):

- measured ZMP: :func:`zmpkit.sensors.zmp_series` of both feet's wrenches with the dataset's
  sensor mounts, minus its mean over the start-up window (the offset paper A's code removes at
  start-up, :func:`zmpkit.sensors.zmp_offset_from_standing_window`); x in the sagittal plane,
  y in the frontal plane;
- expected ZMP: the LIPM-expected ZMP of the commanded lean, :math:`l_{lean}\sin\theta(t)`,
  with :math:`\theta(t) = \operatorname{mean}_j s_j q_{cmd,j}(t)` over
  ``meta["lean_angle_joints"]``;
- steady state: the mean measured ZMP over the last :data:`STEADY_WINDOW_S` of the trial (the
  settled tail of the hold); ``error_pct`` :math:`= 100 (x_{ss} - x_{ref}) / x_{ref}`, none at
  :math:`x_{ref} = 0`; ``overshoot_pct`` from :func:`zmpkit.signals.step_metrics` with
  :math:`y_0 = 0` and :math:`y_\infty = x_{ss}`, none at :math:`x_{ref} = 0`.

A trial whose ZMP is undefined (no foot in contact) anywhere in the steady window has no
steady state: its cells stay empty — never a silent NaN. A trial still oscillating over the
window (peak-to-peak beyond :data:`SETTLED_SPREAD_FRACTION` of the target) keeps its mean but
``settled`` is False, and ``zmpkit sim push`` says so.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.dataset import StepDataset
from zmpkit.experiments.trial_record import StepTrialRecord
from zmpkit.sensors import (
    SensorMount,
    remove_zmp_offset,
    zmp_offset_from_standing_window,
    zmp_series,
)
from zmpkit.signals.step_metrics import step_metrics
from zmpkit.signals.step_trial import StepTrial

__all__ = [
    "STEADY_STATE_COLUMNS",
    "STEADY_WINDOW_S",
    "TrialResponse",
    "dataset_trials",
    "expected_zmp",
    "measured_zmp",
    "step_responses",
    "trial_response",
    "write_steady_state_csv",
]

STEADY_WINDOW_S = 1.0
"""Length of the settled tail, at the end of each trial, averaged for the steady state [s]."""
SETTLED_SPREAD_FRACTION = 0.05
"""A trial counts as settled when its ZMP spans at most this fraction of the target (and at
most :data:`SETTLED_SPREAD_MIN_M`) over the steady window [-]."""
SETTLED_SPREAD_MIN_M = 0.002
"""Smallest peak-to-peak spread that still counts as settled, whatever the target [m]."""
STEADY_STATE_COLUMNS = ("plane", "zmp_ref", "zmp_measured", "error_pct", "overshoot_pct")
"""Columns of ``steady_state.csv``: plane, ZMP target [m], steady measured ZMP [m], [%], [%]."""


@dataclass(frozen=True, eq=False)
class TrialResponse:
    r"""The ZMP response of one trial in its plane.

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        zmp_ref: the ZMP target [m].
        time_since_step: sample times minus ``t_step`` [s], shape (N,).
        zmp_measured: measured ZMP, start-up offset removed [m], NaN where undefined, (N,).
        zmp_expected: :math:`l_{lean}\sin\theta_{cmd}(t)` [m], shape (N,).
        steady_state: mean measured ZMP over the steady window [m]; None if not settled.
        error_pct: :math:`100 (x_{ss} - x_{ref}) / x_{ref}` [%]; None at target 0 or unsettled.
        overshoot_pct: overshoot past the steady state [%]; None at target 0 or unsettled.
        steady_window_s: the averaged window (t0, t1), simulated time [s].
        tail_spread_m: peak-to-peak measured ZMP over the steady window [m]; None if undefined.
    """

    plane: str
    zmp_ref: float
    time_since_step: NDArray[np.float64]
    zmp_measured: NDArray[np.float64]
    zmp_expected: NDArray[np.float64]
    steady_state: float | None
    error_pct: float | None
    overshoot_pct: float | None
    steady_window_s: tuple[float, float]
    tail_spread_m: float | None

    @property
    def settled(self) -> bool:
        """Whether the ZMP is defined and has settled over the steady window.

        Settled: peak-to-peak at most ``max(SETTLED_SPREAD_FRACTION |x_ref|,
        SETTLED_SPREAD_MIN_M)``; otherwise the steady state is the mean of an oscillation and
        a longer hold is needed.
        """
        if self.tail_spread_m is None:
            return False
        limit = max(SETTLED_SPREAD_FRACTION * abs(self.zmp_ref), SETTLED_SPREAD_MIN_M)
        return self.tail_spread_m <= limit


def measured_zmp(
    trial: StepTrialRecord,
    mounts: Mapping[str, SensorMount],
    startup_window: tuple[float, float],
    contact_threshold_n: float,
) -> NDArray[np.float64]:
    """Measured ZMP of ``trial`` in its plane [m], start-up offset removed, NaN where undefined.

    Args:
        trial: the recorded trial.
        mounts: the F-T sensor mounts, ``{"right": ..., "left": ...}``.
        startup_window: quiet standing before the step (t0, t1) [s], whose mean ZMP is the
            offset removed (as paper A's code does at start-up).
        contact_threshold_n: a foot is in contact above this world F_z [N] (the robot's:
            :attr:`~zmpkit.robots.robot.Robot.contact_force_threshold_n`).
    """
    series = zmp_series(
        trial.time,
        trial.right_wrench,
        trial.left_wrench,
        mounts["right"],
        mounts["left"],
        contact_threshold_n=contact_threshold_n,
    )
    offset = zmp_offset_from_standing_window(series, None, startup_window)
    axis = 0 if trial.plane == "sagittal" else 1
    return remove_zmp_offset(series, offset).zmp[:, axis].copy()


def _measured(dataset: StepDataset, index: int) -> NDArray[np.float64]:
    return measured_zmp(
        dataset.trials[index],
        dataset.mounts,
        dataset.startup_window(index),
        dataset.contact_threshold_n,
    )


def expected_zmp(trial: StepTrialRecord, angle_joints: dict[str, float]) -> NDArray[np.float64]:
    r""":math:`l_{lean}\sin\theta_{cmd}(t)` from the commanded joint columns [m]."""
    names = list(trial.joint_names)
    theta = np.mean(
        [s * trial.commanded[:, names.index(j)] for j, s in angle_joints.items()], axis=0
    )
    return trial.lean_length_m * np.sin(theta)


def _steady(
    time: NDArray[np.float64], zmp: NDArray[np.float64], window: tuple[float, float]
) -> tuple[float | None, float | None]:
    """Mean and peak-to-peak of ``zmp`` over ``window`` [m]; None where undefined."""
    inside = (time >= window[0]) & (time <= window[1])
    values = zmp[inside]
    if values.size == 0 or np.any(np.isnan(values)):
        return None, None
    return float(values.mean()), float(np.ptp(values))


def _error_and_overshoot(
    trial: StepTrialRecord, zmp: NDArray[np.float64], steady: float | None
) -> tuple[float | None, float | None]:
    """Steady-state error [%] and overshoot [%]; None at target 0 or without a steady state."""
    ref = trial.target_m
    if steady is None or ref == 0.0:
        return None, None
    ok = ~np.isnan(zmp)
    metrics = step_metrics(
        trial.time[ok], zmp[ok], t_step=trial.t_step_s, initial_value=0.0, final_value=steady
    )
    return 100.0 * (steady - ref) / ref, metrics.overshoot_pct


def trial_response(
    dataset: StepDataset, index: int, steady_window_s: float = STEADY_WINDOW_S
) -> TrialResponse:
    """The measured and expected ZMP of trial ``index`` and its steady-state figures."""
    trial = dataset.trials[index]
    zmp = _measured(dataset, index)
    window = (float(trial.time[-1]) - steady_window_s, float(trial.time[-1]))
    steady, spread = _steady(trial.time, zmp, window)
    ref = trial.target_m
    error, overshoot = _error_and_overshoot(trial, zmp, steady)
    expected = expected_zmp(trial, dict(dataset.meta["lean_angle_joints"]))
    return TrialResponse(
        trial.plane,
        ref,
        trial.time - trial.t_step_s,
        zmp,
        expected,
        steady,
        error,
        overshoot,
        window,
        spread,
    )


def step_responses(
    dataset: StepDataset, steady_window_s: float = STEADY_WINDOW_S
) -> tuple[TrialResponse, ...]:
    """:func:`trial_response` of every trial of ``dataset``, in its order."""
    return tuple(trial_response(dataset, k, steady_window_s) for k in range(len(dataset.trials)))


def _cell(value: float | None, digits: int) -> str:
    return "" if value is None else f"{value:.{digits}g}"


def write_steady_state_csv(responses: tuple[TrialResponse, ...], path: str | Path) -> Path:
    """Write ``steady_state.csv`` with exactly :data:`STEADY_STATE_COLUMNS`; empty = undefined."""
    path = Path(path)
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(STEADY_STATE_COLUMNS)
        for r in responses:
            writer.writerow(
                [
                    r.plane,
                    f"{r.zmp_ref:.10g}",
                    _cell(r.steady_state, 8),
                    _cell(r.error_pct, 6),
                    _cell(r.overshoot_pct, 6),
                ]
            )
    return path


def dataset_trials(dataset: StepDataset) -> list[StepTrial]:
    """A dataset's trials as :class:`~zmpkit.signals.StepTrial` (time from the step) [s, m]."""
    trials = []
    for k, record in enumerate(dataset.trials):
        response = trial_response(dataset, k)
        trials.append(
            StepTrial(
                time=response.time_since_step,
                zmp_measured=response.zmp_measured,
                zmp_ref=record.target_m,
                t_step=0.0,
                plane=record.plane,
                zmp_commanded=record.lean_length_m * math.sin(record.lean_angle_rad),
            )
        )
    return trials
