"""Replay a recorded experiment on the simulator and record the same signals.

- A walk: the re-planned commanded trajectory (:mod:`~zmpkit.simfit.walk_plan`)
  is played by :func:`~zmpkit.experiments.walk_trial.simulate_walk`, exactly as ``zmpkit walk``
  does — open loop, or, for a walk with feedback, with its controller in closed loop
  (:mod:`~zmpkit.simfit.closed_loop`) — and the pitch joints, the F-T ZMP and vertical
  forces and the IMU pitch of the recorded rows are kept (a fallen walk's recording is
  shorter than its plan).
- A step trial: the robot stands ``settle_s`` and then its servos get the recorded
  commanded setpoints, linearly interpolated to every servo tick (the drive streams them at
  the physics rate); the F-T sensors, encoders and IMU are sampled at the recorded times.

- A walk-log window (multiple shooting): from its measured start state, open loop on its
  recorded commands (:mod:`~zmpkit.simfit.shooting`).

A rollout that falls or diverges returns the signals up to that point; the cost charges it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments.walk_trial import simulate_walk
from zmpkit.sensors import zmp_series
from zmpkit.sensors.imu import tilt_from_quaternions
from zmpkit.sim.world import Simulation
from zmpkit.simfit.closed_loop import NOISE_SEED_OFFSET, simulate_closed_loop
from zmpkit.simfit.experiments import Experiment, StepExperiment, WalkExperiment
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.shooting import simulate_window
from zmpkit.simfit.shooting_window import ShootingWindow
from zmpkit.simfit.truth_doc import RobotTruth
from zmpkit.simfit.walk_plan import walk_trajectory

__all__ = [
    "empty_signals",
    "setpoint_table",
    "simulate_experiment",
    "step_readings",
    "step_signals",
    "walk_forces",
]


def simulate_experiment(
    experiment: Experiment, truth: RobotTruth, effects: str, noise_seed: int | None = None
) -> RecordedSignals:
    """The signals the simulator with ``truth`` and ``effects`` records in ``experiment``.

    Args:
        experiment: the recorded experiment to replay.
        truth: the truth object of the experiment's robot.
        effects: effect letters switched on, e.g. ``"M,G"``.
        noise_seed: seed of the sensor noise; None: the fit's (0 open loop and for a log
            window; the recorded walk's plus
            :data:`~zmpkit.simfit.closed_loop.NOISE_SEED_OFFSET` closed loop).

    Returns:
        Signals on the recorded time grid, shorter if the robot fell or the simulation diverged.
    """
    if isinstance(experiment, WalkExperiment):
        return _walk(experiment, truth, effects, noise_seed)
    if isinstance(experiment, ShootingWindow):
        return simulate_window(experiment, truth, effects, noise_seed)
    return _step(experiment, truth, effects, noise_seed)


def _walk(
    experiment: WalkExperiment, truth: RobotTruth, effects: str, noise_seed: int | None
) -> RecordedSignals:

    robot = experiment.robot
    settings = experiment.closed_loop
    try:
        if settings is None:
            trajectory = walk_trajectory(
                experiment.robot,
                experiment.speed_mps,
                experiment.step_duration_s,
                experiment.duration_s,
                experiment.com_height_m,
                experiment.effects or "all",
            )
            sim = robot.make_simulation(effects, truth, seed=noise_seed or 0)
            record = simulate_walk(sim, trajectory)
        else:
            seed = settings.seed + NOISE_SEED_OFFSET if noise_seed is None else noise_seed
            sim = robot.make_simulation(effects, truth, seed=seed)
            record = simulate_closed_loop(settings, sim)
    except SimulationDivergedError:
        return empty_signals(experiment.signals)
    names = experiment.signals.joint_names
    columns = [record.joint(j) for j in names]
    n = experiment.signals.time_s.size
    return RecordedSignals(
        record.time_s[:n],
        names,
        record.q_cmd_rad[:n, columns],
        record.q_meas_rad[:n, columns],
        record.zmp_in_world()[:n],
        record.trunk_pitch_rad[:n],
        walk_forces(record.feet, record.force_in_world[:n]),
    )


def walk_forces(
    feet: tuple[str, ...] | list[str], force_in_world: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The right and left feet's vertical forces ``(rows, 2)`` [N], world z.

    From each foot's force in the world, ``(rows, feet, 3)`` [N], in ``feet``' order.
    """
    return np.stack(
        [force_in_world[:, list(feet).index(side), 2] for side in ("right", "left")], axis=1
    )


def empty_signals(signals: RecordedSignals) -> RecordedSignals:
    """No samples, with the recording's joint names: a rollout that diverged."""
    j = len(signals.joint_names)
    zero = np.zeros((0, j))
    return RecordedSignals(
        np.zeros(0), signals.joint_names, zero, zero, np.zeros((0, 2)), np.zeros(0)
    )


def setpoint_table(signals: RecordedSignals, n_ticks: int, dt: float) -> NDArray[np.float64]:
    """Commanded setpoints at the end of every tick, shape (n_ticks, J) [rad]."""
    t = (np.arange(n_ticks) + 1) * dt
    cmd = signals.q_cmd_rad
    return np.column_stack([np.interp(t, signals.time_s, cmd[:, j]) for j in range(cmd.shape[1])])


def _step(
    experiment: StepExperiment, truth: RobotTruth, effects: str, noise_seed: int | None
) -> RecordedSignals:

    signals = experiment.signals
    robot = experiment.robot
    sim = robot.make_simulation(effects, truth, seed=noise_seed or 0)
    if tuple(sim.joint_names) != tuple(signals.joint_names):
        raise SimulationDivergedError(
            0.0, "the joint list", f"recorded joints differ from {robot.title}'s"
        )
    dt = sim.dt
    sample_ticks = np.round(signals.time_s / dt).astype(int)
    table = setpoint_table(signals, int(sample_ticks[-1]), dt)
    rows: list[NDArray[np.float64]] = []
    wanted = set(sample_ticks.tolist())
    try:
        for k in range(int(sample_ticks[-1])):
            sim.servo.reset(table[k].tolist())
            sim.step(1)
            if k + 1 in wanted:
                rows.append(_sample(sim))
    except SimulationDivergedError:
        if not rows:  # diverged before the first sample
            return empty_signals(signals)
    return step_signals(experiment, np.array(rows), len(rows))


def _sample(sim: Simulation) -> NDArray[np.float64]:
    quat = sim.imu()[2]
    return np.concatenate([sim.ft("right"), sim.ft("left"), sim.encoders(), quat])


def step_signals(experiment: StepExperiment, data: NDArray[np.float64], n: int) -> RecordedSignals:
    """A step trial's signals from ``n`` sample rows ``[F-T right, F-T left, encoders, quat]``."""
    signals = experiment.signals
    if n < 2:
        return empty_signals(signals)
    j = len(signals.joint_names)
    zmp, force, tilt = step_readings(experiment, data[:, :6], data[:, 6:12], data[:, 12 + j :])
    return RecordedSignals(
        signals.time_s[:n],
        signals.joint_names,
        signals.q_cmd_rad[:n],
        data[:, 12 : 12 + j],
        zmp,
        tilt,
        force,
    )


def step_readings(
    experiment: StepExperiment,
    ft_right: NDArray[np.float64],
    ft_left: NDArray[np.float64],
    quats: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """A step trial's ZMP [m], feet's vertical forces [N] and trunk tilt [rad].

    From its first rows (at least two); the forces right then left, world z.

    Args:
        experiment: the step trial (its sample times, mounts and plane).
        ft_right: the right F-T readings, ``(n, 6)`` [N, N·m].
        ft_left: the left F-T readings, ``(n, 6)`` [N, N·m].
        quats: the IMU quaternions (w, x, y, z), ``(n, 4)``.
    """
    time = experiment.signals.time_s[: len(quats)]
    mounts = experiment.mounts
    series = zmp_series(
        time,
        ft_right,
        ft_left,
        mounts["right"],
        mounts["left"],
        contact_threshold_n=experiment.contact_threshold_n,
    )
    force = np.stack([series.fz_right, series.fz_left], axis=1)
    return series.zmp, force, tilt_from_quaternions(quats, experiment.plane)
