r"""One window of a walk log replayed on a candidate simulator (multiple shooting).

The candidate's simulation starts from the window's measured state
(:class:`~zmpkit.simfit.shooting_window.WindowStart`): the driven joints at the encoder
angles and speeds, the base placed by the IMU and the stance sole
(:meth:`~zmpkit.simfit.log_kinematics.LogKinematics.place_base`), the gear deflection and
link flex at their equilibrium under the measured load (:mod:`~zmpkit.simfit.loaded_start`),
the drives' integrals summed from the log, their current (MuJoCo's ``act``) at zero,
the servo's setpoint at the first command moving at the commands' speed. Then its drives
get the recorded commands, linearly interpolated to every physics tick as ``zmpkit walk``
streams its frames, open loop: the same for every candidate. At each scored row the
simulated sensors are read — encoders, the IMU pitch and the ZMP that
:meth:`~zmpkit.simfit.log_kinematics.LogKinematics.readings` computes from the simulated
encoders, IMU and F-T, as for the recording — so any bias of that sensor-only ZMP is the
same on both sides.

A window whose robot tilts past :data:`~zmpkit.experiments.walk_trial.FALL_TILT_RAD` or
whose simulation diverges ends there; the cost charges its missing rows.
"""

from __future__ import annotations

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments.walk_trial import FALL_TILT_RAD
from zmpkit.sensors.imu import quaternion_pitch_roll
from zmpkit.sim.world import Simulation
from zmpkit.simfit.loaded_start import (
    compliance_load,
    compliant_dofs,
    replay_compliance,
    settle_compliance,
)
from zmpkit.simfit.log_kinematics import FEET, LogKinematics
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.shooting_window import ShootingWindow, WindowStart
from zmpkit.simfit.truth_doc import RobotTruth

__all__ = ["drive_integrals", "simulate_window", "start_window"]

_INTEGRATING_DYN = (int(mujoco.mjtDyn.mjDYN_DCMOTOR), int(mujoco.mjtDyn.mjDYN_PID))


def start_window(window: ShootingWindow, sim: Simulation) -> LogKinematics:
    """Put ``sim`` (fresh) in ``window``'s measured start state; its kinematics returned."""
    model, data = sim.model, sim.data
    start = window.start
    kinematics = LogKinematics(model, sim.robot)
    data.qpos[:] = model.qpos0
    data.qvel[:] = 0.0
    data.act[:] = 0.0
    for k, joint in enumerate(sim.joint_names):
        data.qpos[int(model.joint(joint).qposadr[0])] = start.q_rad[k]
        data.qvel[int(model.joint(joint).dofadr[0])] = start.dq_rad_s[k]
    kinematics.place_base(model, data, start.imu_quat_wxyz, start.gyro_rps, start.stance)
    _start_compliance(sim, kinematics, start, float(window.command_time_s[0]))
    kinematics.place_base(model, data, start.imu_quat_wxyz, start.gyro_rps, start.stance)
    drive_integrals(sim, start.error_steps_rad_s)
    data.time = float(window.command_time_s[0])
    sim.servo.reset(window.q_cmd_rad[0].tolist())
    dt_rows = window.command_time_s[1] - window.command_time_s[0]
    sim.servo.velocity = ((window.q_cmd_rad[1] - window.q_cmd_rad[0]) / dt_rows).tolist()
    mujoco.mj_forward(model, data)
    return kinematics


def _start_compliance(
    sim: Simulation, kinematics: LogKinematics, start: WindowStart, start_time_s: float
) -> None:
    """Set the gear deflections and link flex at the start (module docstring).

    With a :class:`~zmpkit.simfit.shooting_window.LoadHistory`, the load of each of its rows
    (measured state placed as at a start, the compliance at zero) is replayed on the
    candidate's springs up to the start's
    (:func:`~zmpkit.simfit.loaded_start.replay_compliance`); without, the start's equilibrium.
    ``sim.data`` holds the start's measured state, which it keeps.
    """
    model, data, robot = sim.model, sim.data, sim.robot
    wrenches = dict(zip(FEET, start.wrenches, strict=True))
    history = start.history
    if history is None:
        settle_compliance(model, data, robot.driven_joints, robot.feet, wrenches)
        return
    joints = compliant_dofs(model, data, robot.driven_joints)
    if joints.size == 0:
        return
    saved_q, saved_v = data.qpos.copy(), data.qvel.copy()
    adr = [(int(model.joint(j).qposadr[0]), int(model.joint(j).dofadr[0])) for j in sim.joint_names]
    qadr, dofadr = np.array([a for a, _ in adr]), np.array([d for _, d in adr])
    loads, inertias = [], []
    for row in range(history.time_s.size):
        data.qpos[qadr] = history.q_rad[row]
        data.qvel[dofadr] = history.dq_rad_s[row]
        kinematics.place_base(
            model, data, history.imu_quat_wxyz[row], history.gyro_rps[row], int(history.stance[row])
        )
        row_wrenches = dict(zip(FEET, history.wrenches[row], strict=True))
        load, inertia = compliance_load(model, data, joints, robot.feet, row_wrenches)
        loads.append(load)
        inertias.append(inertia)
    data.qpos[:], data.qvel[:] = saved_q, saved_v
    load, inertia = compliance_load(model, data, joints, robot.feet, wrenches)
    replay_compliance(
        model,
        data,
        joints,
        np.append(history.time_s, start_time_s),
        np.vstack([*loads, load]),
        np.vstack([*inertias, inertia]),
    )


def drive_integrals(sim: Simulation, error_steps_rad_s: NDArray[np.float64]) -> None:
    r"""Set each drive's integral state from the log's tracking-error steps.

    MuJoCo's ``dcmotor`` and ``pid`` drives integrate ``ctrl - length`` (at the rotor:
    :math:`N (q_{set} - q)`) into their first ``act`` slot, clamped to
    :math:`\pm` ``dynprm[8]`` where that is positive; the steps are summed the same way,
    clamped after each row [rotor rad·s]. A drive without such a state is left as it is.

    Args:
        sim: the candidate's simulation.
        error_steps_rad_s: per row and driven joint, the integral of
            :math:`q_{cmd} - q_{enc}` over the row [rad·s], shape (rows, J).
    """
    model, data = sim.model, sim.data
    ids = [model.actuator(j).id for j in sim.joint_names]
    integrating = [
        k
        for k, i in enumerate(ids)
        if model.actuator_actnum[i] >= 1 and int(model.actuator_dyntype[i]) in _INTEGRATING_DYN
    ]
    if not integrating:
        return
    act = [ids[k] for k in integrating]
    gear = model.actuator_gear[act, 0]
    limit = model.actuator_dynprm[act, 8]
    limit = np.where(limit > 0.0, limit, np.inf)
    total = np.zeros(len(act))
    for step in error_steps_rad_s[:, integrating]:
        total = np.clip(total + gear * step, -limit, limit)
    data.act[model.actuator_actadr[act]] = total


def _row(sim: Simulation, kinematics: LogKinematics) -> NDArray[np.float64]:
    """``[encoders, ZMP x, ZMP y, right F_z, left F_z, pitch]`` as the sensors read now."""
    q = sim.encoders()
    quat = sim.imu()[2]
    wrenches = np.stack([sim.ft(f) for f in FEET])
    zmp, force = kinematics.readings(q, quat, wrenches)
    return np.concatenate((q, zmp, force, [quaternion_pitch_roll(quat)[0]]))


def simulate_window(
    window: ShootingWindow, truth: RobotTruth, effects: str, noise_seed: int | None = None
) -> RecordedSignals:
    """The signals the simulator with ``truth`` and ``effects`` records in ``window``.

    Args:
        window: the window (its measured start, its commands, its scored rows).
        truth: the truth object of the window's robot.
        effects: effect letters switched on, e.g. ``"M,G"``.
        noise_seed: seed of the sensor noise (None: 0, every candidate the same).

    Returns:
        The scored rows' signals, fewer if the robot fell or the simulation diverged.
    """
    sim = window.robot.make_simulation(effects, truth, seed=noise_seed or 0)
    kinematics = start_window(window, sim)
    times, commands = window.command_time_s, window.q_cmd_rad
    scored = window.signals.time_s
    ticks = np.round((times - times[0]) / sim.dt).astype(np.int64)
    rows: list[NDArray[np.float64]] = []
    next_scored = 0
    try:
        for k in range(1, len(times)):
            substeps = max(1, int(ticks[k] - ticks[k - 1]))
            step = (commands[k] - commands[k - 1]) / substeps
            for i in range(1, substeps + 1):
                sim.command(commands[k - 1] + i * step)
                sim.step(1)
            if next_scored < scored.size and times[k] >= scored[next_scored] - 1e-9:
                row = _row(sim, kinematics)
                rows.append(row)
                next_scored += 1
                if abs(row[-1]) > FALL_TILT_RAD:
                    break
    except SimulationDivergedError:
        pass
    return _signals(window, rows)


def _signals(window: ShootingWindow, rows: list[NDArray[np.float64]]) -> RecordedSignals:
    rec = window.signals
    n, j = len(rows), len(rec.joint_names)
    table = np.array(rows).reshape(n, j + 5)
    return RecordedSignals(
        rec.time_s[:n], rec.joint_names, rec.q_cmd_rad[:n], table[:, :j], table[:, j : j + 2],
        table[:, j + 4], table[:, j + 2 : j + 4],
    )  # fmt: skip
