r"""Replicas of any walk log, each window re-cut from the replica's own sensors.

A log that ``zmpkit walk`` did not write (a real robot's, any controller's) cannot be walked
again (:mod:`~zmpkit.simfit.pipeline_replicas`), but each of its windows can be *replayed
again* the way its own scored rows came about: on a robot that is the fitted model, from
an earlier state, and measured by that robot's sensors. Replica ``k`` of a window:

1. the fitted truth (the base truth's sensor specification, noise seed
   :data:`~zmpkit.simfit.adequacy.REPLICA_SEED` + k) replays the log's commands open loop
   from the state measured :data:`~zmpkit.simfit.shooting_window.REPLICA_LEADS` ``[k]``
   burn-ins before the window (the adequacy check's replica start,
   :attr:`~zmpkit.simfit.shooting_window.ShootingWindow.replicas`) to the window's end,
   and its encoders, IMU and F-T are read at every row of the log;
2. those rows replace the log's from that earlier start on, and the window is cut from
   them exactly as :func:`~zmpkit.simfit.shooting_window.log_windows` cuts the data: its
   start state measured from the replica's own encoders, their slope, IMU and loaded sole,
   its gears replayed under the load history those rows hold (the data's rows before the
   earlier start), the drives' integrals summed from the data up to the earlier start and
   from the replica's tracking error after it, its scored rows the replica's readings.

At the window's start the replica's hidden state (gear deflections, gear and base speeds,
winding currents) is the one its own dynamics developed over the lead, and the fit's
estimate of it is made from sensors exactly as it is from the data. Re-fitted
(:mod:`~zmpkit.simfit.refit_intervals`), the replica's move holds what the start-state
estimation does to the estimate — the bias that the noise-only intervals, whose replicas
are scored against rollouts from the *data's* measured starts, leave out
(:mod:`~zmpkit.simfit.noise_intervals`). What it cannot hold is a controller's answer to
other noise: the commands are the log's.

A log's first window has no earlier state: its replica starts at the window's own measured
state. A replica window whose replay falls or diverges, or that starts with no foot in
contact, is left out of that replica.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments.walk_log import WalkLog
from zmpkit.experiments.walk_trial import FALL_TILT_RAD
from zmpkit.sensors.imu import quaternion_pitch_roll
from zmpkit.simfit.adequacy import REPLICA_SEED
from zmpkit.simfit.log_kinematics import FEET, LogKinematics
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.shooting import start_window
from zmpkit.simfit.shooting_window import ShootingWindow, cut_window, replica_experiment
from zmpkit.simfit.truth_doc import RobotTruth, load_robot_truth, truth_doc_with

__all__ = ["replayable_windows", "replayed_readings", "window_replica"]


def replayable_windows(problem: FitProblem) -> bool:
    """Whether every experiment of ``problem`` is a window of a walk log (module docstring)."""
    experiments = problem.experiments
    return bool(experiments) and all(isinstance(e, ShootingWindow) for e in experiments)


def replayed_readings(
    window: ShootingWindow, truth: RobotTruth, effects: str, noise_seed: int
) -> WalkLog | None:
    """The sensor readings of ``window`` replayed by ``truth`` from its start, every row.

    The first row is the window's measured start (the state the replay starts from); every
    later row holds the simulated encoders, IMU (orientation, gyro, accelerometer) and both
    feet's F-T, read after the physics reached the row's time, and the row's command.

    Returns:
        The rows as a log, or None if the robot fell or the simulation diverged first.
    """
    sim = window.robot.make_simulation(effects, truth, seed=noise_seed)
    start_window(window, sim)
    times, commands = window.command_time_s, window.q_cmd_rad
    ticks = np.round((times - times[0]) / sim.dt).astype(np.int64)
    rows = len(times)
    q = np.empty((rows, commands.shape[1]))
    quat, gyro, accel = np.empty((rows, 4)), np.empty((rows, 3)), np.full((rows, 3), np.nan)
    wrenches = np.empty((rows, 2, 6))
    start = window.start
    q[0], quat[0], gyro[0] = start.q_rad, start.imu_quat_wxyz, start.gyro_rps
    wrenches[0] = start.wrenches
    try:
        for k in range(1, rows):
            substeps = max(1, int(ticks[k] - ticks[k - 1]))
            step = (commands[k] - commands[k - 1]) / substeps
            for i in range(1, substeps + 1):
                sim.command(commands[k - 1] + i * step)
                sim.step(1)
            q[k] = sim.encoders()
            gyro[k], accel[k], quat[k] = sim.imu()
            wrenches[k] = np.stack([sim.ft(f) for f in FEET])
            if max(abs(a) for a in quaternion_pitch_roll(quat[k])) > FALL_TILT_RAD:
                return None
    except SimulationDivergedError:
        return None
    feet = {f: wrenches[:, i] for i, f in enumerate(FEET)}
    return WalkLog(
        times.copy(), window.signals.joint_names, commands.copy(), q, quat, gyro,
        feet["right"], feet["left"], accel, window.source,
    )  # fmt: skip


def _replica_window(
    window: ShootingWindow,
    truth: RobotTruth,
    effects: str,
    k: int,
    kinematics: LogKinematics,
) -> ShootingWindow | None:
    """Replica ``k`` of ``window`` (module docstring); None if it fell or lost contact."""
    lead = replica_experiment(window, k)
    readings = replayed_readings(lead, truth, effects, REPLICA_SEED + k)
    if readings is None:
        return None
    log = _spliced(lead, readings)
    before = 0 if lead.start.history is None else lead.start.history.time_s.size
    start_time = float(window.command_time_s[0])
    cut = cut_window(
        log, window.robot, window.log_name, kinematics, start_time, window.window_s,
        window.burn_in_s,
    )  # fmt: skip
    if cut is None:
        return None
    # the drives' integrals: the data's up to the earlier start, the replica's after it
    steps = np.concatenate((lead.start.error_steps_rad_s, cut.start.error_steps_rad_s[before:]))
    return replace(
        cut,
        name=window.name,
        start=replace(cut.start, error_steps_rad_s=steps),
        replicas=(),
        source=window.source,
    )


def _spliced(lead: ShootingWindow, readings: WalkLog) -> WalkLog:
    """The data's load history before ``lead``'s start, then the replica's rows.

    The history rows (no commands recorded there) carry their encoders as commands: their
    tracking error enters through the start's summed integrals instead (:func:`_replica_window`).
    """
    history = lead.start.history
    if history is None:
        return readings
    n = history.time_s.size
    right, left = FEET.index("right"), FEET.index("left")
    return WalkLog(
        np.concatenate((history.time_s, readings.time_s)),
        readings.joint_names,
        np.concatenate((history.q_rad, readings.q_cmd_rad)),
        np.concatenate((history.q_rad, readings.q_enc_rad)),
        np.concatenate((history.imu_quat_wxyz, readings.imu_quat_wxyz)),
        np.concatenate((history.gyro_rps, _gyro(readings))),
        np.concatenate((history.wrenches[:, right], readings.right_wrench)),
        np.concatenate((history.wrenches[:, left], readings.left_wrench)),
        np.concatenate((np.full((n, 3), np.nan), _accel(readings))),
        readings.source,
    )


def _gyro(log: WalkLog) -> NDArray[np.float64]:
    assert log.gyro_rps is not None  # replayed_readings always reads the gyro
    return log.gyro_rps


def _accel(log: WalkLog) -> NDArray[np.float64]:
    assert log.accel_mps2 is not None  # replayed_readings always has the column
    return log.accel_mps2


def window_replica(
    problem: FitProblem, values: NDArray[np.float64] | Sequence[float], k: int
) -> FitProblem | None:
    """Replica ``k`` of ``problem``'s windows replayed by the model at ``values`` [units].

    Returns:
        The same fit problem on the replica's windows (module docstring), or None when no
        window's replay stood.
    """
    vals = np.asarray(values, dtype=float).tolist()
    truth = load_robot_truth(
        problem.robot, truth_doc_with(problem.base_doc, problem.parameters, vals)
    )
    robot = problem.robot
    kinematics = LogKinematics(robot.make_simulation("none").model, robot.description("none"))
    windows = []
    for window in problem.experiments:
        assert isinstance(window, ShootingWindow)  # replayable_windows(problem)
        again = _replica_window(window, truth, problem.sim_effects, k, kinematics)
        if again is not None:
            windows.append(again)
    if not windows:
        return None
    return replace(problem, experiments=tuple(windows))
