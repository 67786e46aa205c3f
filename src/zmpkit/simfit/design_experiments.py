"""The experiments ``identify plan`` weighs, recorded from the nominal robot, and their protocols.

Every robot is offered the designed double-support experiments
(:mod:`zmpkit.experiments.double_support`: a crouch held, a slow squat, a sagittal chirp
sway, a frontal sway), :func:`double_support_designs`. A robot whose fit replays walks
(:attr:`~zmpkit.robots.robot.FitSpec.experiment` ``walk``) is offered open-loop walks that
differ in what the effects respond to: the speed (the swing's and the trunk's
accelerations) and the step duration (the frequency that excites the servo and the
compliances), :func:`walk_designs`. A robot whose fit replays balance steps is offered ZMP
steps of several sizes, :func:`step_designs`. Each is recorded once, from the nominal robot
(the catalogue's nominal values in the robot's truth file), exactly as ``identify sim``
reads a recording.

A chosen experiment is exported as a **protocol** a real robot can run
(:func:`write_protocol`): the joint targets over time of every driven joint
(``targets.csv``: ``time`` [s] then one column per joint [rad]) and ``manifest.yaml``
naming how to start, what to record and at which rate, and how ``identify sim`` reads it.
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import NDArray

from zmpkit.experiments import StepExperimentConfig, run_step_sweep
from zmpkit.experiments.double_support import DESIGNS, double_support_targets
from zmpkit.experiments.double_support_record import record_double_support
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_dataset import write_walk_folder
from zmpkit.robots.robot import Robot
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.truth_doc import truth_doc_with, write_truth_doc
from zmpkit.simfit.walk_plan import walk_trajectory

__all__ = [
    "Design",
    "DoubleSupportDesign",
    "WalkDesign",
    "double_support_designs",
    "record_design",
    "record_step_designs",
    "scratch_folder",
    "step_designs",
    "walk_designs",
    "write_nominal_truth",
    "write_protocol",
]

_WALK_SHARES = ((0.5, 0.5), (1.0, 0.5), (0.75, 0.4), (0.75, 0.6), (1.0, 0.4))
"""(share of the robot's walking speed, step duration [s]) of the candidate walks."""
_STEP_SHARES = (0.2, 0.5, 0.8)
"""Candidate ZMP steps, as shares of the robot's largest balance target [-]."""
_FIT_FOLDER = (
    "zmpkit identify sim FOLDER --robot ROBOT, the recording written as a step dataset "
    "(meta.json + one trial CSV: time, right_/left_ F-T wrench, enc_ and cmd_ of every "
    "driven joint, imu_; zmpkit.experiments.dataset)"
)
_FIT_WALK = (
    "zmpkit identify sim WALK_FOLDER --robot ROBOT, the recording written as a zmpkit walk "
    "folder: summary.json with this command and timeseries.csv with time_s, each pitch "
    "joint's _cmd_rad and _meas_rad, trunk_pitch_rad, zmp_x_m, zmp_y_m"
)
_RECORD = [
    "commanded angle of every driven joint [rad]",
    "encoder angle of every driven joint [rad]",
    "both ankle F-T wrenches, sensor frame [N, N·m]",
    "IMU orientation (quaternion) of the torso",
]


@dataclass(frozen=True)
class WalkDesign:
    """A candidate open-loop walk.

    Attributes:
        speed_mps: forward speed [m/s].
        step_duration_s: one step [s].
        duration_s: walking time [s].
    """

    speed_mps: float
    step_duration_s: float
    duration_s: float

    @property
    def name(self) -> str:
        """Its folder and row name."""
        return f"walk_{self.speed_mps:g}mps_{self.step_duration_s:g}s_{self.duration_s:g}s"


@dataclass(frozen=True)
class DoubleSupportDesign:
    """A candidate designed double-support experiment.

    Attributes:
        design: one of :data:`~zmpkit.experiments.double_support.DESIGNS`.
    """

    design: str

    @property
    def name(self) -> str:
        """Its folder and row name."""
        return self.design


Design = WalkDesign | DoubleSupportDesign
"""A candidate experiment with a protocol."""


def walk_designs(robot: Robot, duration_s: float) -> list[WalkDesign]:
    """The candidate walks of ``robot`` (module docstring), each ``duration_s`` long."""
    walking = robot.require_walking()
    out = []
    for share, step_s in _WALK_SHARES:
        speed = round(share * walking.speed_mps, 4)
        fastest = walking.max_step_length_m / step_s
        if speed <= fastest and duration_s >= 2 * step_s:
            out.append(WalkDesign(speed, step_s, duration_s))
    return out


def double_support_designs() -> list[DoubleSupportDesign]:
    """The designed double-support experiments, every robot's."""
    return [DoubleSupportDesign(d) for d in DESIGNS]


def step_designs(robot: Robot) -> tuple[float, ...]:
    """The candidate ZMP step targets of ``robot`` [m] (module docstring)."""
    span = robot.require_balance().max_target_m
    return tuple(round(share * span, 6) for share in _STEP_SHARES)


def write_nominal_truth(base_doc: dict, parameters: tuple[FitParameter, ...], folder: Path) -> Path:
    """The robot's truth with every fitted parameter at its catalogue nominal, in ``folder``."""
    doc = truth_doc_with(base_doc, parameters, [p.nominal for p in parameters])
    return write_truth_doc(doc, folder / "nominal_truth.yaml")


def record_design(
    robot: Robot, design: Design, truth: Path, effects: str, seed: int, out: Path
) -> Path | None:
    """Record ``design`` open loop from ``truth`` into ``out/<name>``; None if it fell."""
    if isinstance(design, DoubleSupportDesign):
        targets = double_support_targets(robot, design.design)
        return record_double_support(robot, targets, effects, str(truth), seed, out / design.name)
    config = WalkConfig(
        robot=robot,
        speed_mps=design.speed_mps,
        step_duration_s=design.step_duration_s,
        duration_s=design.duration_s,
        effects=effects,
        seed=seed,
        truth=str(truth),
        figures=False,
    )
    trial = run_walk_trial(config)
    if trial.record.fell:
        return None
    joints = robot.require_walking().series_joints
    return write_walk_folder(out / design.name, trial.summary, trial.pattern, trial.record, joints)


def record_step_designs(
    robot: Robot, targets: tuple[float, ...], truth: Path, effects: str, seed: int, out: Path
) -> Path:
    """Record the candidate ZMP steps from ``truth`` as one step dataset in ``out``."""
    config = StepExperimentConfig(
        robot=robot, targets_m=targets, effects=effects, seed=seed, settle_s=2.0, truth=str(truth)
    )
    return Path(run_step_sweep(config, out / "steps", workers=1).path)


def write_protocol(robot: Robot, design: Design, folder: Path) -> Path:
    """Write ``design`` as a protocol a real robot runs (module docstring); returns the folder.

    A walk's targets are the plan's whole-body IK
    (:func:`~zmpkit.simfit.walk_plan.walk_trajectory`), the trajectory ``identify sim``
    re-plans from the walk's command; a double-support experiment's are its solved targets.
    """
    if isinstance(design, DoubleSupportDesign):
        targets = double_support_targets(robot, design.design)
        time_s, names, q = targets.time_s, targets.joint_names, targets.q_rad
        kind: dict = {"design": design.design, "plane": targets.plane}
        start = (
            "stand at rest in the simulator's standing pose (every driven joint at the first "
            "row's angle), feet flat on level ground; then play the rows at their times as "
            "position targets, no feedback"
        )
        fit = _FIT_FOLDER
    else:
        walking = robot.require_walking()
        trajectory = walk_trajectory(
            robot, design.speed_mps, design.step_duration_s, design.duration_s,
            walking.com_height_m,
        )  # fmt: skip
        time_s, names, q = trajectory.time_s, trajectory.joint_names, trajectory.q_rad
        kind = {
            "speed_mps": design.speed_mps,
            "step_duration_s": design.step_duration_s,
            "duration_s": design.duration_s,
            "com_height_m": walking.com_height_m,
        }
        start = (
            "stand at rest in the first row's pose, feet flat on level ground; then play the "
            "rows at their times as position targets, no feedback"
        )
        fit = _FIT_WALK
    return _write(robot, folder, time_s, names, q, kind, start, fit)


def _write(
    robot: Robot, folder: Path, time_s: NDArray[np.float64], names: tuple[str, ...],
    q: NDArray[np.float64], command: dict, start: str, fit: str,
) -> Path:  # fmt: skip
    """``targets.csv`` and ``manifest.yaml`` of one protocol in ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    header = ",".join(("time", *names))
    table = np.column_stack([time_s, q])
    np.savetxt(folder / "targets.csv", table, delimiter=",", header=header, comments="", fmt="%.6f")
    period = float(np.median(np.diff(time_s)))
    manifest = {
        "experiment": "double support" if "design" in command else "open-loop walk",
        "robot": robot.name,
        "command": command,
        "targets": {"file": "targets.csv", "period_s": round(period, 6), "unit": "rad"},
        "start": start,
        "record": {"rate_hz_at_least": round(1.0 / period), "signals": _RECORD},
        "fit": fit,
    }
    path = folder / "manifest.yaml"
    path.write_text(yaml.safe_dump(manifest, sort_keys=False, allow_unicode=True), "utf-8")
    return folder


def scratch_folder() -> Path:
    """A temporary folder for the nominal truth while recording."""
    return Path(tempfile.mkdtemp(prefix="zmpkit-plan-"))
