"""The walk experiment: a walk config in, the planned and the recorded walk out.

Paper B §III: a 3D-LIPM walk (preview control) solved by whole-body IK and played open-loop
on the walking robot, whose servos track the IK's joint angles with the chosen effects on. What
it records is what a user of the real robot reads — encoders, IMU, foot F-T sensors, joint
torques (a real robot estimates them from its motor currents) — plus the feet and torso
positions of a motion capture; the truth file is read only by the simulator.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mujoco

from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import WalkSummary, summarise_walk
from zmpkit.experiments.walk_trial import ProgressCallback, WalkRecord, simulate_walk
from zmpkit.robots.registry import get_robot
from zmpkit.sim.world import Simulation
from zmpkit.walking import generate_pattern
from zmpkit.walking.heading_feedback import HeadingFeedbackGains
from zmpkit.walking.ik import IkSettings, JointTrajectory, solve_walking_ik
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.walk_controllers import (
    DcmWalk,
    OpenLoopWalk,
    ReferenceAdapter,
    SensorLayout,
    WalkController,
    ZmpIpWalk,
)

__all__ = ["WalkTrial", "make_controller", "run_walk_trial", "sensor_layout"]


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


def sensor_layout(sim: Simulation, sole_sites: Mapping[str, str]) -> SensorLayout:
    """Where the simulated robot's sensors sit: its F-T sites, sole centres and IMU site.

    Args:
        sim: the simulation (its F-T sensors and IMU).
        sole_sites: foot -> site at its sole centre (the IK's).
    """
    model = sim.model
    orientation = sim.robot.imu.orientation
    sensor = model.sensor(orientation)
    imu_site = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, int(sensor.objid[0]))
    return SensorLayout(
        sole_sites={f.foot: sole_sites[f.foot] for f in sim.robot.feet},
        sensor_sites={f.foot: f.site for f in sim.robot.feet},
        imu_site=str(imu_site),
        contact_threshold_n=sim.robot.contact_force_threshold_n,
    )


def make_controller(
    name: str,
    pattern: WalkingPattern,
    trajectory: JointTrajectory,
    model: mujoco.MjModel,
    settings: IkSettings,
    sim: Simulation,
    heading_feedback: bool = True,
    reference_adapter: ReferenceAdapter | None = None,
) -> WalkController:
    """The walking controller ``name`` for this walk (``open``, ``zmpip`` or ``dcm``).

    ``heading_feedback`` False switches the feedback walks' IMU yaw feedback off;
    ``reference_adapter`` adapts ``zmpip``'s ZMP reference online (paper B's Algorithm 2).

    Raises:
        ParameterError: a reference adapter for a controller that tracks no ZMP reference.
    """
    if reference_adapter is not None and name != "zmpip":
        raise ParameterError(
            f"an online ZMP reference adapter needs the zmpip controller (it adapts the "
            f"reference of zmpip's preview control); got {name!r}"
        )
    if name == "open":
        return OpenLoopWalk(trajectory)
    layout = sensor_layout(sim, settings.sole_sites)
    heading = None if heading_feedback else HeadingFeedbackGains(gain_per_step=0.0)
    if name == "zmpip":
        return ZmpIpWalk(pattern, model, settings, layout, sim.joint_names, heading_gains=heading,
                         reference_adapter=reference_adapter)  # fmt: skip
    return DcmWalk(pattern, model, settings, layout, sim.joint_names, heading_gains=heading)


def run_walk_trial(config: WalkConfig, progress: ProgressCallback | None = None) -> WalkTrial:
    """Plan, solve the IK, simulate and summarise one walk.

    Args:
        config: the walk.
        progress: called with (simulated time, total time) [s] during the simulation.
    """
    robot = get_robot(config.robot, needs="walking")
    pattern = generate_pattern(config.pattern_config())
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    sim = robot.make_simulation(config.effects, config.truth, seed=config.seed)
    controller = make_controller(
        config.controller, pattern, trajectory, model, settings, sim, config.heading_feedback
    )
    record = simulate_walk(
        sim, trajectory, progress, controller=controller, pushes=config.pushes,
        faults=config.faults,
    )  # fmt: skip
    pushes = [f"{p.force_n:g}@{p.time_s:g}:{p.direction}" for p in config.pushes]
    summary = summarise_walk(pattern, trajectory, record, config.effects, config.seed, pushes)
    return WalkTrial(config, pattern, trajectory, record, summary)
