"""Play a designed double-support experiment on the simulator and write it as a step dataset.

The targets of :mod:`zmpkit.experiments.double_support` are played open loop, tick by tick,
exactly as the simulator fit replays a step trial (:func:`zmpkit.simfit.rollout`'s step
path: at tick ``k`` the servo's setpoints are the targets interpolated at ``(k + 1) dt``,
the sensors sampled at the targets' times), and written in the step-dataset layout
(:mod:`zmpkit.experiments.dataset`: ``meta.json`` + one trial CSV with both F-T wrenches,
every encoder, every commanded setpoint and the IMU) that ``zmpkit identify sim`` reads and
a real robot's recording of the same protocol can be written in. The dataset's
``settings.design`` names the experiment; its trial's ``target_m`` is 0 (no ZMP step), its
``t_step_s`` the time the crouch is reached.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit import __version__
from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments.config import trial_file_name
from zmpkit.experiments.dataset import (
    DATASET_FORMAT,
    column_units,
    write_meta,
    write_trial_csv,
)
from zmpkit.experiments.double_support import DoubleSupportTargets
from zmpkit.experiments.trial_record import StepTrialRecord
from zmpkit.robots.robot import Robot

__all__ = ["record_double_support"]


def record_double_support(
    robot: Robot,
    targets: DoubleSupportTargets,
    effects: str,
    truth: str | None,
    seed: int,
    out: Path,
) -> Path | None:
    """Play ``targets`` on ``robot`` (``effects``, ``truth``) and write ``out``; None on a fall.

    A run whose simulation diverges, or whose feet leave the floor (the sum of both F-T
    sensors' vertical force below half the robot's weight at any sample), is not written.
    """
    sim = robot.make_simulation(effects, truth, seed=seed)
    dt = sim.dt
    ticks = np.round(targets.time_s / dt).astype(int)
    wanted = {int(k): i for i, k in enumerate(ticks)}
    setpoints = np.column_stack(
        [
            np.interp((np.arange(int(ticks[-1])) + 1) * dt, targets.time_s, targets.q_rad[:, j])
            for j in range(targets.q_rad.shape[1])
        ]
    )
    rows = []
    try:
        for k in range(int(ticks[-1])):
            sim.servo.reset(setpoints[k].tolist())
            sim.step(1)
            if k + 1 in wanted:
                gyro, accel, quat = sim.imu()
                rows.append(
                    np.concatenate([sim.ft("right"), sim.ft("left"), sim.encoders(), gyro,
                                    accel, quat])
                )  # fmt: skip
    except SimulationDivergedError:
        return None
    data = np.array(rows)
    first = data[: max(1, len(rows) // 10)]
    weight = float(np.median(first[:, 2] + first[:, 8]))
    if np.any(data[:, 2] + data[:, 8] < 0.5 * weight):
        return None
    j = len(targets.joint_names)
    record = StepTrialRecord(
        plane=targets.plane,
        target_m=0.0,
        t_step_s=targets.ramp_s,
        lean_angle_rad=0.0,
        lean_length_m=0.0,
        joint_names=targets.joint_names,
        time=targets.time_s.copy(),
        right_wrench=data[:, 0:6],
        left_wrench=data[:, 6:12],
        encoders=data[:, 12 : 12 + j],
        commanded=targets.q_rad.copy(),
        imu=data[:, 12 + j :],
    )
    out.mkdir(parents=True, exist_ok=True)
    name = trial_file_name(targets.plane, 0.0)
    write_trial_csv(record, out / name)
    write_meta(_meta(robot, targets, effects, truth, seed, name), out)
    return out


def _meta(
    robot: Robot, targets: DoubleSupportTargets, effects: str, truth: str | None, seed: int,
    file: str,
) -> dict:  # fmt: skip
    """``meta.json`` of a one-trial designed experiment (module docstring)."""
    return {
        "format": DATASET_FORMAT,
        "robot": robot.source,
        "plane": targets.plane,
        "effects": effects,
        "seed": seed,
        "settings": {"design": targets.name, "settle_s": 0.0, "truth": truth, "push": None},
        "joint_names": list(targets.joint_names),
        "sensor_mounts": robot.feet_mounts(),
        "contact_threshold_n": robot.contact_force_threshold_n,
        "units": column_units(targets.joint_names),
        "zmpkit_version": __version__,
        "lean_length_m": 0.0,
        "lean_angle_joints": {},
        "trials": [
            {
                "file": file,
                "target_m": 0.0,
                "t_step_s": targets.ramp_s,
                "lean_angle_rad": 0.0,
                "startup_window_s": [0.0, 0.0],
            }
        ],
    }
