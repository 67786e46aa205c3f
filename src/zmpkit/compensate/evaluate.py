"""Simulate one walk with a corrected ZMP reference and measure its trunk oscillation.

The walk is ``zmpkit walk``'s: the pattern of :class:`~zmpkit.experiments.walk_config.WalkConfig`
with ``zmp_offset`` added to its linear reference, the whole-body IK on the design model,
and the simulated walking robot with the configured effects. The oscillation metrics are those of
``summary.json`` over the steady walk: the trunk-pitch spectrum's amplitude at the step
frequency and the trunk pitch's standard deviation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments.walk import walk_controller
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import WalkSummary, summarise_walk
from zmpkit.experiments.walk_trial import WalkRecord, simulate_walk
from zmpkit.walking import generate_pattern
from zmpkit.walking.ik import JointTrajectory, solve_walking_ik
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["FALL_PENALTY_RAD", "WalkOutcome", "oscillation_of", "simulate_with_offset"]

FALL_PENALTY_RAD = 1.0
"""Oscillation metric given to a walk that fell or diverged [rad] (worse than any walk)."""


@dataclass(frozen=True)
class WalkOutcome:
    """One simulated walk and its oscillation.

    Attributes:
        config: the walk.
        pattern: the planned walk (reference + offset).
        trajectory: the IK's joint angles.
        record: the simulated signals (None when the simulation diverged).
        summary: the walk's metrics (None when the simulation diverged).
        step_peak_rad: trunk-pitch spectrum amplitude at the step frequency [rad].
        std_rad: trunk-pitch standard deviation over the steady walk [rad].
        fell: whether the robot fell or the simulation diverged.
    """

    config: WalkConfig
    pattern: WalkingPattern
    trajectory: JointTrajectory
    record: WalkRecord | None
    summary: WalkSummary | None
    step_peak_rad: float
    std_rad: float
    fell: bool


def oscillation_of(summary: WalkSummary | None) -> tuple[float, float, bool]:
    """(step-frequency amplitude [rad], std [rad], fell) of a summary; penalised if it fell."""
    if summary is None or summary.fell:
        return FALL_PENALTY_RAD, FALL_PENALTY_RAD, True
    peak = summary.trunk_pitch_step_frequency_amplitude_rad
    std = summary.trunk_pitch_std_rad
    if peak is None or std is None:
        return FALL_PENALTY_RAD, FALL_PENALTY_RAD, True
    return peak, std, False


def simulate_with_offset(
    config: WalkConfig, zmp_offset: NDArray[np.float64] | None = None
) -> WalkOutcome:
    """Plan ``config``'s walk with ``zmp_offset`` [m] (N, 2) on the reference and simulate it.

    The walk runs with ``config.controller``: with feedback, the offset moves the reference
    the controller tracks (paper B compensates its closed-loop walk this way).
    """
    robot = config.robot
    pattern = generate_pattern(config.pattern_config(), zmp_offset)
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    sim = robot.make_simulation(config.effects, config.truth, seed=config.seed)
    controller = walk_controller(config, robot, pattern, trajectory, model, sim)
    try:
        record = simulate_walk(sim, trajectory, controller=controller)
    except SimulationDivergedError:
        return WalkOutcome(config, pattern, trajectory, None, None, *oscillation_of(None))
    summary = summarise_walk(pattern, trajectory, record, config.effects, config.seed)
    return WalkOutcome(config, pattern, trajectory, record, summary, *oscillation_of(summary))
