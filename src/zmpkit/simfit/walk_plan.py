"""The commanded joint trajectory of a walk, re-planned from its command.

A walk folder records the commanded angles of the pitch joints only; the simulator needs
all of them. The walk is re-planned (3D-LIPM preview pattern, whole-body IK on the rigid
design model — what the robot's own walking engine computed) from its speed, step duration,
duration and CoM height, and the result is checked against the recorded commanded angles.
Plans are cached per process: each worker computes a walk's trajectory once.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

from zmpkit.errors import InputFileError
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.ik import JointTrajectory, solve_walking_ik

__all__ = ["COMMAND_TOLERANCE_RAD", "match_walk_plan", "walk_trajectory"]

_PROBE_DURATION_S = 1.0
COMMAND_TOLERANCE_RAD = 1e-4
"""Largest difference between the re-planned and the recorded commanded angle [rad]."""


@lru_cache(maxsize=16)
def walk_trajectory(
    robot: str, speed_mps: float, step_duration_s: float, duration_s: float, com_height_m: float
) -> JointTrajectory:
    """Pattern + IK of ``robot``'s walk (cached) [rad per joint per motion frame]."""
    config = PatternConfig(
        command=WalkCommand(v_x=speed_mps),
        duration_s=duration_s,
        gait=GaitParameters(step_duration_s=step_duration_s),
        com_height_m=com_height_m,
    )
    walker = get_robot(robot, needs="walking")
    return solve_walking_ik(generate_pattern(config), walker.ik_model(), walker.ik_settings)


def _pattern_end(speed_mps: float, step_duration_s: float, duration_s: float) -> float:

    config = PatternConfig(
        command=WalkCommand(v_x=speed_mps),
        duration_s=duration_s,
        gait=GaitParameters(step_duration_s=step_duration_s),
    )
    return float(generate_pattern(config).time_s[-1])


def match_walk_plan(
    robot: str, path: Path, speed_mps: float, step_duration_s: float, signals: RecordedSignals
) -> tuple[float, float]:
    """The (duration [s], CoM height [m]) whose plan reproduces the recorded commands.

    Raises:
        InputFileError: naming ``path`` if no plan reproduces the commanded angles.
    """
    overhead = _pattern_end(speed_mps, step_duration_s, _PROBE_DURATION_S) - _PROBE_DURATION_S
    t_last = float(signals.time_s[-1])
    duration = round(t_last - overhead, 2)  # the CSV keeps 7 digits; frames are 10 ms
    if duration <= 0.0:
        raise InputFileError(path, f"a walk of {t_last} s is shorter than its standing phases")
    height = get_robot(robot, needs="walking").require_walking().com_height_m
    trajectory = walk_trajectory(robot, speed_mps, step_duration_s, duration, height)
    names = signals.joint_names
    columns = [trajectory.joint_names.index(j) for j in names]
    planned = trajectory.q_rad[:, columns]
    recorded = signals.q_cmd_rad
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
    return duration, height
