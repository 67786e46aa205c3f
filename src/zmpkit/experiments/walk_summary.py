"""The numbers of one walk (``summary.json``): fall, speed, trunk oscillation, feet.

Paper B §III reports the trunk oscillation (its spectrum peaks at the step frequency), the
actual vs commanded speed, and traces the speed difference to the feet: the distance between
the feet in double support (step length) and their slip while they stand. Every metric is
taken over the steady walk (see :func:`steady_window`).

A fall is a fall: a walk that fell has every metric None, whatever it did before. Falls are
a tilt past the limit (``roll``, ``pitch``), the torso too low (``height``) — both stop the
simulation (:mod:`zmpkit.experiments.walk_trial`) — or a ``stall``: over two consecutive
steps the torso progressed less than :data:`STALL_PROGRESS_RATIO` of the commanded distance
(straight walks of at least :data:`STALL_MIN_SPEED_MPS`; a turning walk is not judged).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.signals.contact_phases import (
    double_support_distance,
    fitted_speed,
    foot_slip,
    path_speed,
)
from zmpkit.signals.spectra import amplitude_spectrum
from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.step_events import NOT_CAPTURED, StepEvent

__all__ = [
    "HEADING_TOLERANCE_RAD",
    "MIN_WINDOW_S",
    "STALL_MIN_SPEED_MPS",
    "STALL_PROGRESS_RATIO",
    "WalkSummary",
    "heading_error",
    "measured_double_support_distance",
    "planned_double_support_distance",
    "stall_time",
    "steady_window",
    "summarise_walk",
]

MIN_WINDOW_S = 1.0
"""Shortest steady window that gives metrics [s]."""
STALL_PROGRESS_RATIO = 0.5
"""A walk stalls when two steps progress less than this share of the commanded distance [-]."""
HEADING_TOLERANCE_RAD = 0.05
"""A walk keeps its heading if the IMU's stays within this of the plan's [rad]."""
STALL_MIN_SPEED_MPS = 0.02
"""Commanded speeds below this are not judged for stalls [m/s]."""


@dataclass(frozen=True)
class WalkSummary:
    """The contract of ``summary.json`` (the first eight fields are required by the CLI).

    Attributes:
        fell: whether the robot fell.
        mean_speed_mps: fitted torso speed along x over the steady walk [m/s] (a turning
            walk's is its chord's: see ``path_speed_mps``).
        commanded_speed_mps: commanded speed [m/s].
        trunk_pitch_peak_hz: largest peak of the trunk-pitch spectrum above 0.5 Hz [Hz].
        trunk_pitch_peak_amplitude_rad: its amplitude [rad].
        trunk_pitch_std_rad: standard deviation of the trunk pitch [rad].
        mean_double_support_foot_distance_m: mean distance of the feet along the heading in
            double support [m].
        foot_slip_m: mean horizontal sole displacement over a stance phase [m].
        foot_slip_x_m: the same along x; negative = backwards [m].
        planned_speed_mps: the planned CoM's fitted speed over the same window [m/s].
        planned_double_support_foot_distance_m: the planned feet distance in double support [m].
        step_frequency_hz: 1 / step duration [Hz].
        trunk_pitch_step_frequency_amplitude_rad: spectrum amplitude at the step frequency [rad].
        fall_time_s: time of the fall [s], or None.
        window_s: the steady window (start, end) [s].
        effects: the effects that were on.
        seed: the sensor-noise seed.
        ik_max_com_error_m: largest CoM error the IK left [m].
        ik_max_foot_error_m: largest foot error the IK left [m].
        fall_kind: ``roll``, ``pitch``, ``height`` or ``stall``; None when it stood.
        controller: the walking controller (``open``, ``zmpip``, ``dcm``).
        commanded_lateral_speed_mps: commanded leftward speed [m/s].
        commanded_turn_rate_rps: commanded yaw rate [rad/s].
        clamped_step_limits: the footstep limits that shortened a step (empty: none did;
            then the walk is slower than commanded).
        pushes: the pushes, as ``FORCE_N@TIME_S:DIR``.
        heading_error_max_rad: largest |IMU yaw − planned heading| over the whole walk, both
            taken from their start values [rad]; None after a fall or without an IMU yaw.
        heading_error_end_rad: the same at the end of the walk (signed, counter-clockwise
            positive) [rad].
        path_speed_mps: the torso's speed along its path over the steady walk, its sway
            averaged over a gait cycle (:func:`~zmpkit.signals.contact_phases.path_speed`)
            [m/s]; equals ``mean_speed_mps`` on a straight walk along x, and is the speed a
            turning or sideways walk actually makes; None after a fall or on a window shorter
            than two gait cycles.
        adjusted_steps: how many steps the walk moved to capture its DCM
            (:mod:`zmpkit.walking.step_adjustment`).
        uncaptured_steps: how many of them no admissible step could capture.
        step_events: each adjusted step in words (when, where it landed, whether it captured).
    """

    fell: bool
    mean_speed_mps: float | None
    commanded_speed_mps: float
    trunk_pitch_peak_hz: float | None
    trunk_pitch_peak_amplitude_rad: float | None
    trunk_pitch_std_rad: float | None
    mean_double_support_foot_distance_m: float | None
    foot_slip_m: float | None
    foot_slip_x_m: float | None
    planned_speed_mps: float | None
    planned_double_support_foot_distance_m: float | None
    step_frequency_hz: float
    trunk_pitch_step_frequency_amplitude_rad: float | None
    fall_time_s: float | None
    window_s: tuple[float, float]
    effects: str
    seed: int
    ik_max_com_error_m: float
    ik_max_foot_error_m: float
    fall_kind: str | None = None
    controller: str = "open"
    commanded_lateral_speed_mps: float = 0.0
    commanded_turn_rate_rps: float = 0.0
    clamped_step_limits: tuple[str, ...] = ()
    pushes: tuple[str, ...] = ()
    heading_error_max_rad: float | None = None
    heading_error_end_rad: float | None = None
    path_speed_mps: float | None = None
    adjusted_steps: int = 0
    uncaptured_steps: int = 0
    step_events: tuple[str, ...] = ()


def heading_error(pattern: WalkingPattern, record: WalkRecord) -> NDArray[np.float64] | None:
    """IMU yaw minus the planned heading [rad], both from their start values, shape (N,).

    e(t) = (ψ_IMU(t) − ψ_IMU(0)) − (ψ_plan(t) − ψ_plan(0)), with ψ_plan the plan's torso yaw
    (the mean of the feet's) at the record's times; None without a recorded IMU yaw.
    """
    if record.trunk_yaw_rad is None:
        return None
    feet = pattern.feet
    plan = np.interp(record.time_s, feet.time_s, feet.torso_yaw_in_world)
    yaw = record.trunk_yaw_rad
    return (yaw - yaw[0]) - (plan - plan[0])


def steady_window(pattern: WalkingPattern, record: WalkRecord) -> tuple[float, float]:
    """From the end of the second step to one step before the last one ends, or the fall [s]."""
    steps = pattern.footsteps.steps
    step_s = pattern.footsteps.gait.step_duration_s
    start = steps[min(1, len(steps) - 1)].t_end
    end = steps[-1].t_end - step_s
    if record.fall_time_s is not None:
        end = min(end, record.fall_time_s)
    return float(start), float(end)


def stall_time(pattern: WalkingPattern, record: WalkRecord) -> float | None:
    """End of the first two-step window whose progress was under half the commanded [s].

    Windows slide by one step over the steady walk (:func:`steady_window`: the start and the
    stop, where the plan itself is slower, are not judged). Progress is the torso's
    displacement (motion capture) along the commanded direction;
    None when the walk never stalled or is not judged (turning, or slower than
    :data:`STALL_MIN_SPEED_MPS`).
    """
    command = pattern.config.command
    speed = math.hypot(command.v_x, command.v_y)
    if command.omega != 0.0 or speed < STALL_MIN_SPEED_MPS:
        return None
    direction = np.array([command.v_x, command.v_y]) / speed
    span = 2.0 * pattern.footsteps.gait.step_duration_s
    time, torso = record.time_s, record.torso_in_world[:, :2]
    t, end = steady_window(pattern, record)
    while t + span <= end + 1e-9:
        i0, i1 = np.searchsorted(time, [t, t + span])
        i1 = min(int(i1), time.size - 1)
        progress = float((torso[i1] - torso[int(i0)]) @ direction)
        if progress < STALL_PROGRESS_RATIO * speed * span:
            return float(time[i1])
        t += span / 2.0
    return None


def _mean(values: NDArray[np.float64]) -> float | None:
    finite = values[np.isfinite(values)]
    return float(np.mean(finite)) if finite.size else None


def _planned_distance(pattern: WalkingPattern, mask: NDArray[np.bool_]) -> float | None:
    return _mean(planned_double_support_distance(pattern)[mask])


def planned_double_support_distance(pattern: WalkingPattern) -> NDArray[np.float64]:
    """The planned feet's distance along the heading in double support [m] (pattern grid).

    NaN off planned double support; the footstep plan as walked (shortened steps included).
    """
    feet = pattern.feet
    soles = np.stack([feet.left.position_in_world, feet.right.position_in_world], axis=1)
    contact = np.column_stack([feet.left.in_contact, feet.right.in_contact])
    return double_support_distance(soles, contact, feet.torso_yaw_in_world)


def measured_double_support_distance(
    pattern: WalkingPattern, record: WalkRecord
) -> NDArray[np.float64]:
    """The soles' distance along the planned heading in double support [m] (record grid).

    The heading is the plan's torso yaw at each sample; NaN off double support.
    """
    feet = pattern.feet
    heading = np.interp(record.time_s, feet.time_s, feet.torso_yaw_in_world)
    return double_support_distance(record.sole_in_world, record.in_contact(), heading)


def _trunk(record: WalkRecord, mask: NDArray[np.bool_], step_hz: float) -> dict[str, float]:
    pitch = record.trunk_pitch_rad[mask]
    spectrum = amplitude_spectrum(pitch, float(np.median(np.diff(record.time_s))))
    peak_hz, peak_amplitude = spectrum.peak()
    return {
        "trunk_pitch_peak_hz": peak_hz,
        "trunk_pitch_peak_amplitude_rad": peak_amplitude,
        "trunk_pitch_std_rad": float(np.std(pitch)),
        "trunk_pitch_step_frequency_amplitude_rad": spectrum.at(step_hz),
    }


def _feet(
    record: WalkRecord,
    pattern: WalkingPattern,
    mask: NDArray[np.bool_],
    planned_mask: NDArray[np.bool_],
) -> dict[str, float | None]:
    contact = record.in_contact()
    distance = measured_double_support_distance(pattern, record)
    slip = foot_slip(record.sole_in_world, contact, mask)
    return {
        "mean_double_support_foot_distance_m": _mean(distance[mask]),
        "planned_double_support_foot_distance_m": _planned_distance(pattern, planned_mask),
        "foot_slip_m": slip.mean_abs_m if slip.phases else None,
        "foot_slip_x_m": slip.mean_x_m if slip.phases else None,
    }


def _describe(event: StepEvent) -> str:
    """One adjusted step in words, e.g. ``4.19 s, step 6 (left): landed (+0.4, +10.7) cm ...``."""
    dx, dy = (100.0 * v for v in event.shift_m)
    text = (
        f"{event.time_s:.2f} s, step {event.step} ({event.side}): landed ({dx:+.1f}, {dy:+.1f}) "
        f"cm from the plan, {event.shortened_s:.2f} s early"
    )
    if event.captured:
        return text
    return f"{text}; {NOT_CAPTURED} ({100.0 * event.dcm_error_left_m:.1f} cm left)"


def _fall(pattern: WalkingPattern, record: WalkRecord) -> tuple[str | None, float | None]:
    """How and when [s] the walk fell, a stall counted as a fall; (None, None): it stood."""
    fall_kind, fall_time = record.fall_kind, record.fall_time_s
    if record.fell and fall_kind is None:
        fall_kind = "tilt"  # a record from before fall kinds were told apart
    if not record.fell:
        stalled = stall_time(pattern, record)
        if stalled is not None:
            fall_kind, fall_time = "stall", stalled
    return fall_kind, fall_time


def _steady_metrics(
    pattern: WalkingPattern,
    record: WalkRecord,
    window: tuple[float, float],
    step_hz: float,
    fell: bool,
) -> dict[str, float | None]:
    """The metrics of the steady ``window`` [s]; all None after a fall or in a short one."""
    time = record.time_s
    mask = (time >= window[0]) & (time <= window[1])
    metrics: dict[str, float | None] = dict.fromkeys(
        ("mean_speed_mps", "planned_speed_mps", "trunk_pitch_peak_hz",
         "trunk_pitch_peak_amplitude_rad", "trunk_pitch_std_rad",
         "trunk_pitch_step_frequency_amplitude_rad", "mean_double_support_foot_distance_m",
         "planned_double_support_foot_distance_m", "foot_slip_m", "foot_slip_x_m",
         "heading_error_max_rad", "heading_error_end_rad", "path_speed_mps"),
    )  # fmt: skip
    if not fell and window[1] - window[0] >= MIN_WINDOW_S:
        planned_mask = (pattern.time_s >= window[0]) & (pattern.time_s <= window[1])
        metrics["mean_speed_mps"] = fitted_speed(time, record.torso_in_world[:, 0], mask)
        cycle_s = 2.0 / step_hz  # two steps: the sway's period
        sampled = time[mask]  # the window as sampled: a sample short of its bounds at most
        if sampled.size >= 3 and sampled[-1] - sampled[0] >= 2.0 * cycle_s:
            xy = record.torso_in_world[:, :2]
            metrics["path_speed_mps"] = path_speed(time, xy, mask, cycle_s)
        com_x = pattern.com_position_in_world[:, 0]
        metrics["planned_speed_mps"] = fitted_speed(pattern.time_s, com_x, planned_mask)
        metrics.update(_trunk(record, mask, step_hz))
        metrics.update(_feet(record, pattern, mask, planned_mask))
        error = heading_error(pattern, record)
        if error is not None and error.size:
            metrics["heading_error_max_rad"] = float(np.max(np.abs(error)))
            metrics["heading_error_end_rad"] = float(error[-1])
    return metrics


def summarise_walk(
    pattern: WalkingPattern,
    trajectory: JointTrajectory,
    record: WalkRecord,
    effects: str,
    seed: int,
    pushes: Sequence[str] = (),
) -> WalkSummary:
    """The summary of one simulated walk (see :class:`WalkSummary`).

    Args:
        pattern: the planned walk.
        trajectory: its IK.
        record: what the robot did.
        effects: the effects that were on.
        seed: the sensor-noise seed.
        pushes: the pushes, as ``FORCE_N@TIME_S:DIR``.
    """
    step_hz = 1.0 / pattern.footsteps.gait.step_duration_s
    fall_kind, fall_time = _fall(pattern, record)
    fell = fall_kind is not None
    window = steady_window(pattern, record)
    metrics = _steady_metrics(pattern, record, window, step_hz, fell)
    command = pattern.config.command
    return WalkSummary(
        fell=fell,
        commanded_speed_mps=float(command.v_x),
        step_frequency_hz=step_hz,
        fall_time_s=fall_time,
        window_s=window,
        effects=effects,
        seed=seed,
        ik_max_com_error_m=trajectory.max_com_error_m,
        ik_max_foot_error_m=trajectory.max_foot_error_m,
        fall_kind=fall_kind,
        controller=record.controller,
        commanded_lateral_speed_mps=float(command.v_y),
        commanded_turn_rate_rps=float(command.omega),
        clamped_step_limits=pattern.footsteps.clamped_limits,
        pushes=tuple(pushes),
        adjusted_steps=len(record.step_events),
        uncaptured_steps=sum(not e.captured for e in record.step_events),
        step_events=tuple(_describe(e) for e in record.step_events),
        **{
            k: (None if v is None or not math.isfinite(v) else float(v)) for k, v in metrics.items()
        },
    )
