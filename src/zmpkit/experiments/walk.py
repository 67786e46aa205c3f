"""The walk experiment: a walk config in, the planned and the recorded walk out.

Paper B §III: a 3D-LIPM walk (preview control) solved by whole-body IK and played open-loop
on the walking robot, whose servos track the IK's joint angles with the chosen effects on. What
it records is what a user of the real robot reads — encoders, IMU, foot F-T sensors, joint
torques (a real robot estimates them from its motor currents) — plus the feet and torso
positions of a motion capture; the truth file is read only by the simulator.
"""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import WalkSummary, summarise_walk
from zmpkit.experiments.walk_trial import ProgressCallback, WalkRecord, simulate_walk
from zmpkit.robots.registry import get_robot
from zmpkit.walking import generate_pattern
from zmpkit.walking.ik import JointTrajectory, solve_walking_ik
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["WalkTrial", "run_walk_trial"]


@dataclass(frozen=True)
class WalkTrial:
    """One walk: what was planned and what the robot recorded.

    Attributes:
        config: what was asked.
        pattern: the planned walk.
        trajectory: the IK's joint angles and errors.
        record: the simulated signals.
        summary: the metrics of ``summary.json``.
    """

    config: WalkConfig
    pattern: WalkingPattern
    trajectory: JointTrajectory
    record: WalkRecord
    summary: WalkSummary


def run_walk_trial(config: WalkConfig, progress: ProgressCallback | None = None) -> WalkTrial:
    """Plan, solve the IK, simulate and summarise one walk.

    Args:
        config: the walk.
        progress: called with (simulated time, total time) [s] during the simulation.
    """
    robot = get_robot(config.robot, needs="walking")
    pattern = generate_pattern(config.pattern_config())
    trajectory = solve_walking_ik(pattern, robot.ik_model(), robot.ik_settings)
    sim = robot.make_simulation(config.effects, config.truth, seed=config.seed)
    record = simulate_walk(sim, trajectory, progress)
    summary = summarise_walk(pattern, trajectory, record, config.effects, config.seed)
    return WalkTrial(config, pattern, trajectory, record, summary)
