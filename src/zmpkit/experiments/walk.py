"""The walk experiment: a walk config in, the planned and the recorded walk out.

Paper B §III: a 3D-LIPM walk (preview control) solved by whole-body IK and played open-loop
on the walking robot, whose servos track the IK's joint angles with the chosen effects on. What
it records is what a user of the real robot reads — encoders, IMU, foot F-T sensors, joint
torques (a real robot estimates them from its motor currents) — plus the feet and torso
positions of a motion capture; the truth file is read only by the simulator.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import WalkSummary, summarise_walk
from zmpkit.experiments.walk_trial import ProgressCallback, WalkRecord, simulate_walk
from zmpkit.robots.robot import Robot, WalkingDefaults
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.world import Simulation
from zmpkit.walking import generate_pattern
from zmpkit.walking.dcm_parameters import DcmParameters
from zmpkit.walking.heading_feedback import HeadingFeedbackGains
from zmpkit.walking.ik import IkSettings, JointTrajectory, solve_walking_ik
from zmpkit.walking.multibody_zmp import expected_zmp_offset
from zmpkit.walking.online_walk import WalkPlant
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.servo_feedforward import servo_compliance_offsets
from zmpkit.walking.step_adjustment import StepAdjustmentParameters
from zmpkit.walking.walk_controllers import (
    DcmWalk,
    OffsetWalk,
    OpenLoopWalk,
    ReferenceAdapter,
    SensorLayout,
    WalkController,
    ZmpIpWalk,
)
from zmpkit.walking.zmp_observer import ZmpObserverParameters

__all__ = [
    "IK_REALISABLE_M",
    "WalkTrial",
    "check_realisable",
    "make_controller",
    "run_walk_trial",
    "sensor_layout",
    "soft_servo_stiffness",
    "walk_controller",
]


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
    servo_stiffness_nm_per_rad: float | None = None,
    observer_com_noise_m: float | None = None,
    servo_damping_nm_s_per_rad: float = 0.0,
    observer_zmp_noise_m: float | None = None,
    reference_adapter: ReferenceAdapter | None = None,
    step_adjustment: bool = False,
) -> WalkController:
    """The walking controller ``name`` for this walk (``open``, ``zmpip`` or ``dcm``).

    ``heading_feedback`` False switches the feedback walks' IMU yaw feedback off. With
    ``servo_stiffness_nm_per_rad`` (the robot's P-only servos' gain, joint side [N·m/rad]),
    the targets carry the planned joint torques (plus ``servo_damping_nm_s_per_rad`` times
    the planned joint speeds) over it
    (:func:`~zmpkit.walking.servo_feedforward.servo_compliance_offsets`).
    ``observer_com_noise_m`` and ``observer_zmp_noise_m`` replace the ZMP/IP observer's
    default σ_c and σ_p [m] (in ``dcm``'s DCM observer too). ``reference_adapter`` adapts
    ``zmpip``'s ZMP reference online (paper B's Algorithm 2).

    Raises:
        ParameterError: a reference adapter for a controller that tracks no ZMP reference.
    """
    if reference_adapter is not None and name != "zmpip":
        raise ParameterError(
            f"an online ZMP reference adapter needs the zmpip controller (it adapts the "
            f"reference of zmpip's preview control); got {name!r}"
        )
    controller: WalkController
    if name == "open":
        controller = OpenLoopWalk(trajectory)
    else:
        layout = sensor_layout(sim, settings.sole_sites)
        plant: WalkPlant = (pattern, model, settings, layout, sim.joint_names)
        noise = (observer_com_noise_m, observer_zmp_noise_m)
        controller = _feedback_walk(
            name, plant, trajectory, heading_feedback, noise, reference_adapter,
            step_adjustment, servo_stiffness_nm_per_rad,
        )  # fmt: skip
    if servo_stiffness_nm_per_rad is None:
        return controller
    offsets = servo_compliance_offsets(
        pattern, trajectory, model, settings, servo_stiffness_nm_per_rad,
        servo_damping_nm_s_per_rad,
    )  # fmt: skip
    return OffsetWalk(controller, offsets)


def _feedback_walk(
    name: str,
    plant: WalkPlant,
    trajectory: JointTrajectory,
    heading_feedback: bool,
    noise: tuple[float | None, float | None],
    reference_adapter: ReferenceAdapter | None,
    step_adjustment: bool,
    servo_stiffness_nm_per_rad: float | None = None,
) -> WalkController:
    """The feedback walk ``name`` (``zmpip`` or ``dcm``) of :func:`make_controller`.

    ``noise``: the observer's σ_c and σ_p [m] (None: its default).
    ``servo_stiffness_nm_per_rad``: the soft servos' gain, over which both walks feed the
    ZMP shift they ask for forward (:mod:`zmpkit.walking.zmp_shift_feedforward`; None: none).
    """
    heading = None if heading_feedback else HeadingFeedbackGains(gain_per_step=0.0)
    observer = ZmpObserverParameters()
    observer = replace(
        observer,
        com_noise_m=noise[0] or observer.com_noise_m,
        zmp_noise_m=noise[1] or observer.zmp_noise_m,
    )
    stepping = StepAdjustmentParameters(enabled=step_adjustment)
    if name == "zmpip":
        pattern, model = plant[0], plant[1]
        expected = expected_zmp_offset(model, trajectory, pattern.com.zmp_in_world)
        return ZmpIpWalk(
            *plant, parameters=observer, heading_gains=heading,
            reference_adapter=reference_adapter, stepping=stepping,
            expected_zmp_offset_in_world=expected,
            servo_stiffness_nm_per_rad=servo_stiffness_nm_per_rad,
        )  # fmt: skip
    dcm = DcmParameters(observer=observer)
    return DcmWalk(
        *plant, parameters=dcm, heading_gains=heading, stepping=stepping,
        servo_stiffness_nm_per_rad=servo_stiffness_nm_per_rad,
    )  # fmt: skip


def soft_servo_stiffness(walking: WalkingDefaults, effects: str) -> float | None:
    """The servo gain the walk's feed-forward inverts [N·m/rad], or None for none.

    The robot's soft servos are its motor effect: with ``M`` off its joints are the stiff
    ideal servos, which a feed-forward for soft ones would only push off their targets.
    """
    return walking.servo_stiffness_nm_per_rad if EffectSet.parse(effects).motor else None


def walk_controller(
    config: WalkConfig,
    robot: Robot,
    pattern: WalkingPattern,
    trajectory: JointTrajectory,
    model: mujoco.MjModel,
    sim: Simulation,
    reference_adapter: ReferenceAdapter | None = None,
) -> WalkController:
    """:func:`make_controller` for ``config``'s walk with ``robot``'s own walking settings.

    ``model`` is the robot's IK model the trajectory was solved on.

    The controller, heading feedback, step adjustment and effects come from ``config``; the
    soft servos' feed-forward and the observer's noise levels from the robot's walking
    defaults.
    """
    walking = robot.require_walking()
    return make_controller(
        config.controller, pattern, trajectory, model, robot.ik_settings, sim,
        config.heading_feedback, soft_servo_stiffness(walking, config.effects),
        walking.observer_com_noise_m, walking.servo_damping_nm_s_per_rad,
        walking.observer_zmp_noise_m, reference_adapter, config.step_adjustment,
    )  # fmt: skip


IK_REALISABLE_M = 0.005
"""A plan is realisable when the whole-body IK follows its CoM and soles within this [m].

The shipped robots' walks leave at most 0.14 mm (a turning walk); a leg that cannot reach
its footstep leaves centimetres, and the walk then falls for a reason that is not the
robot's balance."""


AT_LIMIT_RAD = 1e-3
"""A joint this close to its range's end is at its limit [rad]."""


def check_realisable(trajectory: JointTrajectory, model: mujoco.MjModel | None = None) -> None:
    """Refuse a walk whose plan the robot's legs cannot follow (:data:`IK_REALISABLE_M`).

    Args:
        trajectory: the whole-body IK's solution of the plan.
        model: the IK's model; when given, the message names the leg joints at their limits
            when the plan is missed most (the usual cause: an ankle's short range).

    Raises:
        ParameterError: naming the largest CoM and sole errors, when, what holds the legs
            back, and what to change.
    """
    com, foot = trajectory.max_com_error_m, trajectory.max_foot_error_m
    if max(com, foot) <= IK_REALISABLE_M:
        return
    t_com = float(trajectory.time_s[int(np.argmax(trajectory.com_error_m))])
    t_foot = float(trajectory.time_s[int(np.argmax(trajectory.foot_error_m))])
    worst = int(np.argmax(np.maximum(trajectory.com_error_m, trajectory.foot_error_m)))
    limits = _at_limits(trajectory, model, worst) if model is not None else ""
    raise ParameterError(
        f"the robot's legs cannot follow this walk's plan: the whole-body IK leaves the CoM "
        f"{1e3 * com:.1f} mm off (at {t_com:.2f} s) and a sole {1e3 * foot:.1f} mm off (at "
        f"{t_foot:.2f} s), more than {1e3 * IK_REALISABLE_M:g} mm{limits}; try a lower --speed "
        "or --step-duration, or check the robot file's legs and walking: com_height, crouch, "
        "torso_pitch, zmp_forward (`zmpkit robot init` chooses the last three where a leg "
        "joint holds the upright crouch at its limit)"
    )


def _at_limits(trajectory: JointTrajectory, model: mujoco.MjModel, row: int) -> str:
    """``"; at T s J is at its lower limit (X rad)"`` for the joints at a limit at ``row``."""
    found = []
    for name, angle in zip(trajectory.joint_names, trajectory.q_rad[row], strict=True):
        joint = model.joint(name).id
        if not model.jnt_limited[joint]:
            continue
        low, high = (float(v) for v in model.jnt_range[joint])
        for end, value in (("lower", low), ("upper", high)):
            if abs(float(angle) - value) <= AT_LIMIT_RAD:
                found.append(f"{name} at its {end} limit ({value:.3f} rad)")
    if not found:
        return ""
    return f"; at {float(trajectory.time_s[row]):.2f} s {', '.join(found)}"


def run_walk_trial(
    config: WalkConfig,
    progress: ProgressCallback | None = None,
    *,
    realisable_only: bool = False,
) -> WalkTrial:
    """Plan, solve the IK, simulate and summarise one walk.

    Args:
        config: the walk.
        progress: called with (simulated time, total time) [s] during the simulation.
        realisable_only: refuse, before simulating, a plan the IK cannot follow
            (:func:`check_realisable`); else simulate it (the summary keeps the IK's errors).
    """
    robot = config.robot
    pattern = generate_pattern(config.pattern_config())
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    if realisable_only:
        check_realisable(trajectory, model)
    sim = robot.make_simulation(config.effects, config.truth, seed=config.seed)
    controller = walk_controller(config, robot, pattern, trajectory, model, sim)
    record = simulate_walk(
        sim, trajectory, progress, controller=controller, pushes=config.pushes,
        faults=config.faults,
    )  # fmt: skip
    pushes = [f"{p.force_n:g}@{p.time_s:g}:{p.direction}" for p in config.pushes]
    summary = summarise_walk(pattern, trajectory, record, config.effects, config.seed, pushes)
    return WalkTrial(config, pattern, trajectory, record, summary)
