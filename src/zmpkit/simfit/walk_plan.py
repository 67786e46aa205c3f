"""The commanded joint trajectory of a walk, re-planned from its command.

A walk folder records the commanded angles of the pitch joints only; the simulator needs
all of them. The walk is re-planned (3D-LIPM preview pattern, whole-body IK on the rigid
design model — what the robot's own walking engine computed) from its speed, step duration,
duration and CoM height, and the result is checked against the recording: an open-loop
walk's commanded angles (:func:`match_walk_plan`), or, for a walk with feedback whose
commands the controller corrected, the planned ZMP reference and CoM the folder records
(:func:`match_closed_loop_plan`). Plans are cached per process: each worker computes a
walk's trajectory once.

**A walk that fell** is kept up to :data:`FALL_MARGIN_S` before its last reproduced row: the
last moments of a fall are the robot tipping over its sole edge, which says more about
when it tipped than about its drives. Its walking time is unknown (the recording stops at
the fall), but a plan depends on it only through its number of steps, and the fall came
after ``t_fall - standing phases``: plans of :data:`FALL_PLAN_CANDIDATES` step counts from
there are tried, the first that reproduces every recorded row is taken (a fall before the
stop: every longer plan agrees), else the one that reproduces most, and only the rows it
reproduces are kept.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError
from zmpkit.experiments.walk import soft_servo_stiffness
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.robots.robot import Robot
from zmpkit.simfit.closed_loop import WalkSettings, planned_references
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.walking import generate_pattern
from zmpkit.walking.ik import JointTrajectory, solve_walking_ik
from zmpkit.walking.servo_feedforward import servo_compliance_offsets

__all__ = [
    "COMMAND_TOLERANCE_RAD",
    "FALL_MARGIN_S",
    "FALL_PLAN_CANDIDATES",
    "MIN_ROWS",
    "REFERENCE_TOLERANCE_M",
    "PlanMatch",
    "match_closed_loop_plan",
    "match_walk_plan",
    "probe_duration_s",
    "walk_trajectory",
]

_PROBE_DURATION_S = 1.0


def probe_duration_s(step_duration_s: float) -> float:
    """A walking time near :data:`_PROBE_DURATION_S` of whole steps (at least two) [s].

    A pattern walks ``round(duration / T)`` steps, so the standing phases' overhead is the
    pattern's end less the walking time only for a whole number of steps: with 0.4 s steps
    a 1.0 s probe walks two (0.8 s), and an overhead taken against 1.0 s is 0.2 s short.
    """
    return max(2, round(_PROBE_DURATION_S / step_duration_s)) * step_duration_s


COMMAND_TOLERANCE_RAD = 1e-4
"""Largest difference between the re-planned and the recorded commanded angle [rad]."""
REFERENCE_TOLERANCE_M = 1e-5
"""Largest difference between the re-planned and the recorded ZMP reference or CoM [m]
(the CSV keeps 7 significant digits: 1e-7 m on a 1 m walk)."""
FALL_MARGIN_S = 0.5
"""A fallen walk is fitted up to this long before its last reproduced row [s]."""
FALL_PLAN_CANDIDATES = 6
"""How many step counts a fallen walk's plan is tried with (module docstring) [-]."""
MIN_ROWS = 16
"""Fewest rows a walk keeps to be fitted [-]."""


@dataclass(frozen=True)
class PlanMatch:
    """The plan that reproduces a recorded walk.

    Attributes:
        duration_s: walking time of the plan [s].
        com_height_m: CoM height of the plan [m].
        rows: the recorded rows the fit keeps (all of a complete walk; a fallen walk's up to
            :data:`FALL_MARGIN_S` before its last reproduced row) [-].
    """

    duration_s: float
    com_height_m: float
    rows: int


def _fallen_plan(
    path: Path,
    time_s: NDArray[np.float64],
    durations: list[float],
    error_of: Callable[[float], NDArray[np.float64]],
    tolerance: float,
) -> tuple[float, int]:
    """(walking time [s], rows kept) of a fallen walk (module docstring).

    ``error_of(duration)`` is the re-planned walk's error per recorded row (inf past its end).
    """
    best, matched = durations[0], -1
    for duration in durations:
        bad = np.flatnonzero(~(error_of(duration) <= tolerance))
        end = int(bad[0]) if bad.size else time_s.size
        if end > matched:
            best, matched = duration, end
        if end == time_s.size:
            break
    if matched <= 0:
        raise InputFileError(path, "the re-planned walk differs from its first recorded row")
    return best, _kept_rows(path, time_s, matched)


def _kept_rows(path: Path, time_s: NDArray[np.float64], end: int) -> int:
    """A fallen walk's rows before its first unreproduced one ``end``, less the fall margin."""
    rows = int(np.searchsorted(time_s, time_s[end - 1] - FALL_MARGIN_S, side="right"))
    if rows < MIN_ROWS:
        raise InputFileError(
            path,
            f"the walk fell at {time_s[-1]:.2f} s: {rows} rows before it (less "
            f"{FALL_MARGIN_S} s) are fewer than {MIN_ROWS}; nothing to fit",
        )
    return rows


@lru_cache(maxsize=16)
def walk_trajectory(
    robot: Robot,
    speed_mps: float,
    step_duration_s: float,
    duration_s: float,
    com_height_m: float,
    effects: str | None = None,
) -> JointTrajectory:
    r"""The joint targets of ``robot``'s open-loop walk (cached) [rad per joint per frame].

    The pattern's whole-body IK; with ``effects`` (the walk's, ``summary.json``), on a robot
    whose soft P-only servos the walk pre-loads
    (:func:`~zmpkit.experiments.walk.soft_servo_stiffness`), plus the feed-forward offsets
    :math:`(\tau_{ff} + b \dot q) / k` that ``zmpkit walk`` added from the first frame after
    its start pose (the start pose is the plan's own).
    """
    config = WalkConfig(
        robot, speed_mps, step_duration_s, duration_s, com_height_m=com_height_m
    ).pattern_config()
    pattern = generate_pattern(config)
    trajectory = solve_walking_ik(pattern, robot.ik_model(), robot.ik_settings)
    walking = robot.require_walking()
    stiffness = None if effects is None else soft_servo_stiffness(walking, effects)
    if stiffness is None:
        return trajectory
    offsets = servo_compliance_offsets(
        pattern, trajectory, robot.ik_model(), robot.ik_settings, stiffness,
        walking.servo_damping_nm_s_per_rad,
    )  # fmt: skip
    offsets[0] = 0.0
    return replace(trajectory, q_rad=trajectory.q_rad + offsets)


def _pattern_end(
    robot: Robot, speed_mps: float, step_duration_s: float, duration_s: float
) -> float:
    """When ``robot``'s walk of ``duration_s`` ends, its standing phases included [s]."""
    config = WalkConfig(robot, speed_mps, step_duration_s, duration_s).pattern_config()
    return float(generate_pattern(config).time_s[-1])


def _fall_durations(overhead_s: float, t_last: float, step_duration_s: float) -> list[float]:
    """Walking times [s] of the step counts a walk that fell at ``t_last`` [s] may have had."""
    first = max(1, int(np.floor((t_last - overhead_s) / step_duration_s)))
    return [round(n * step_duration_s, 6) for n in range(first, first + FALL_PLAN_CANDIDATES)]


def _padded_error(planned: NDArray[np.float64], recorded: NDArray[np.float64]) -> NDArray:
    """Largest error per recorded row; inf for rows past the plan's end."""
    n = min(len(planned), len(recorded))
    error = np.full(len(recorded), np.inf)
    error[:n] = np.abs(planned[:n] - recorded[:n]).max(axis=1)
    return error


def _walk_duration(path: Path, overhead_s: float, t_last: float) -> float:
    """The walking time of a complete recording ending at ``t_last`` [s]."""
    duration = round(t_last - overhead_s, 2)  # the CSV keeps 7 digits; frames are 10 ms
    if duration <= 0.0:
        raise InputFileError(path, f"a walk of {t_last} s is shorter than its standing phases")
    return duration


def match_walk_plan(
    robot: Robot,
    path: Path,
    speed_mps: float,
    step_duration_s: float,
    signals: RecordedSignals,
    fell: bool = False,
    effects: str | None = None,
) -> PlanMatch:
    """The open-loop plan whose commanded angles reproduce the recorded ones.

    ``effects``: the effects the walk ran with (:func:`walk_trajectory`), None if unknown.

    Raises:
        InputFileError: naming ``path`` if no plan reproduces the commanded angles.
    """
    probe_s = probe_duration_s(step_duration_s)
    overhead = _pattern_end(robot, speed_mps, step_duration_s, probe_s) - probe_s
    height = robot.require_walking().com_height_m
    names = signals.joint_names
    recorded = signals.q_cmd_rad

    def planned_of(duration: float) -> NDArray[np.float64]:
        trajectory = walk_trajectory(robot, speed_mps, step_duration_s, duration, height, effects)
        return trajectory.q_rad[:, [trajectory.joint_names.index(j) for j in names]]

    t_last = float(signals.time_s[-1])
    if fell:
        durations = _fall_durations(overhead, t_last, step_duration_s)
        duration, rows = _fallen_plan(
            path,
            signals.time_s,
            durations,
            lambda d: _padded_error(planned_of(d), recorded),
            COMMAND_TOLERANCE_RAD,
        )
        return PlanMatch(duration, height, rows)
    duration = _walk_duration(path, overhead, t_last)
    planned = planned_of(duration)
    if planned.shape != recorded.shape:
        raise InputFileError(
            path, f"{recorded.shape[0]} rows, but the re-planned walk has {planned.shape[0]} frames"
        )
    error = np.abs(planned - recorded).max(axis=0)
    worst = int(np.argmax(error))
    if error[worst] > COMMAND_TOLERANCE_RAD:
        raise InputFileError(
            path,
            f"the re-planned walk ({speed_mps} m/s, {step_duration_s} s steps, CoM "
            f"{height} m) differs from the recorded command by "
            f"{error[worst]:.3g} rad; expected a zmpkit walk with its default pattern",
            column=f"{names[worst]}_cmd_rad",
        )
    return PlanMatch(duration, height, recorded.shape[0])


def match_closed_loop_plan(
    path: Path,
    settings: WalkSettings,
    time_s: NDArray[np.float64],
    references_m: NDArray[np.float64],
    fell: bool = False,
) -> PlanMatch:
    """The plan of a walk with feedback whose ZMP reference and CoM reproduce the recorded.

    Args:
        path: the walk's time series (named in errors).
        settings: the walk's settings; ``duration_s`` is ignored (found here).
        time_s: the recorded times [s].
        references_m: the recorded ``zmp_ref_x, zmp_ref_y, com_ref_x, com_ref_y`` [m].
        fell: whether the walk fell (the recording stops there).

    Raises:
        InputFileError: naming ``path`` if no plan reproduces the recorded references.
    """
    probe = replace(settings, duration_s=probe_duration_s(settings.step_duration_s))
    overhead = float(generate_pattern(probe.walk_config().pattern_config()).time_s[-1])
    overhead -= probe.duration_s
    n = len(references_m)
    if fell:
        durations = _fall_durations(overhead, float(time_s[-1]), settings.step_duration_s)
        duration, rows = _fallen_plan(
            path,
            time_s,
            durations,
            lambda d: _padded_error(
                planned_references(replace(settings, duration_s=d)), references_m
            ),
            REFERENCE_TOLERANCE_M,
        )
        return PlanMatch(duration, settings.com_height_m, rows)
    duration = _walk_duration(path, overhead, float(time_s[-1]))
    planned = planned_references(replace(settings, duration_s=duration))
    if planned.shape != references_m.shape:
        raise InputFileError(path, f"{n} rows, but the re-planned walk has {len(planned)} frames")
    error = np.abs(planned - references_m).max(axis=0)
    worst = int(np.argmax(error))
    if error[worst] > REFERENCE_TOLERANCE_M:
        column = ("zmp_ref_x_m", "zmp_ref_y_m", "com_ref_x_m", "com_ref_y_m")[worst]
        raise InputFileError(
            path,
            f"the re-planned {settings.controller} walk ({settings.speed_mps} m/s, "
            f"{settings.step_duration_s} s steps) differs from the recorded plan by "
            f"{error[worst]:.3g} m; expected a zmpkit walk with its default pattern",
            column=column,
        )
    return PlanMatch(duration, settings.com_height_m, n)
