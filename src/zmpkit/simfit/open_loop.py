"""An experiment as open-loop input: what every candidate's servos get, step by step.

A step trial and a walk played open loop are open loop: the walk plays its planned frames
through the servo (no controller reads a sensor), the step trial its recorded setpoints; so the
servo
setpoints of every physics step are known before the rollout starts, and they are the same
for every candidate (candidates differ in the model, not in the command). A walk with a
feedback controller (:mod:`~zmpkit.simfit.closed_loop`) has no schedule: its commands follow
each candidate's motion (:func:`is_open_loop`). A candidate's
rollout starts from its :class:`~zmpkit.sim.world.Simulation` built and posed exactly as the
serial path (:mod:`~zmpkit.simfit.rollout`) starts its loop.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError, SimulationDivergedError
from zmpkit.experiments.walk_trial import start_pose
from zmpkit.robots.robot import Robot
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.posed import PosedSimulation, StartedSimulation
from zmpkit.sim.world import Simulation
from zmpkit.simfit.candidate_worlds import CandidateWorlds
from zmpkit.simfit.experiments import Experiment, StepExperiment, WalkExperiment
from zmpkit.simfit.rollout import setpoint_table
from zmpkit.simfit.shooting_window import ShootingWindow
from zmpkit.simfit.truth_doc import RobotTruth
from zmpkit.simfit.walk_plan import walk_trajectory

__all__ = [
    "OpenLoopSchedule",
    "is_open_loop",
    "open_loop_schedule",
    "posed_simulation",
    "posed_simulations",
    "posed_world_simulations",
]


def is_open_loop(experiment: Experiment) -> bool:
    """Whether ``experiment`` runs as a schedule from a posed simulation (a batch's rollout).

    A walk with a feedback controller does not (its commands follow the candidate); nor
    does a walk-log window (:mod:`~zmpkit.simfit.shooting`): its commands are known, but it
    starts from a measured state the batches do not set, so it runs on the serial path.
    """
    if isinstance(experiment, ShootingWindow):
        return False
    return not isinstance(experiment, WalkExperiment) or experiment.closed_loop is None


@dataclass(frozen=True)
class OpenLoopSchedule:
    """An experiment as open-loop input, the same for every candidate.

    Step counts are the simulation's own (``Simulation._steps``: 0 when built).

    Attributes:
        setpoints_rad: servo setpoints of the steps after ``start_step``, in the
            simulation's joint order [rad], shape (nstep, J).
        start_step: the step of the posed simulation the batch continues from [-].
        record_steps: the steps after which a signal row is read, increasing, shape (R,);
            those at ``start_step`` are read from the posed simulation.
        q_cmd_rad: the commanded angles of each row, the experiment's joints [rad], (R, Je).
    """

    setpoints_rad: NDArray[np.float64]
    start_step: int
    record_steps: NDArray[np.int64]
    q_cmd_rad: NDArray[np.float64]


def posed_simulation(experiment: Experiment, truth: RobotTruth, effects: str) -> Simulation:
    """A candidate's simulation where the serial path starts its loop."""
    sim = experiment.robot.make_simulation(effects, truth, seed=0)
    _pose(experiment, sim)
    return sim


def posed_simulations(
    experiments: Sequence[Experiment], truths: Sequence[RobotTruth], effects: str
) -> list[list[Simulation]]:
    """Per experiment, per candidate, what :func:`posed_simulation` returns.

    Each candidate's description is built and its MJCF compiled once per robot, not once
    per experiment: its other experiments' simulations start from copies of that model
    (a copy costs about a fifth of a compilation), which is the host's main cost in a
    generation of a GPU batch.
    """
    out: list[list[Simulation]] = [[] for _ in experiments]
    for truth in truths:
        built: dict[Robot, tuple[RobotDescription, mujoco.MjModel]] = {}
        for e, experiment in enumerate(experiments):
            if experiment.robot in built:  # the first one's model, untouched by posing
                description, model = built[experiment.robot]
                sim = Simulation(description, seed=0, model=copy.copy(model))
            else:
                description = experiment.robot.description(effects, truth)
                sim = Simulation(description, seed=0)
                built[experiment.robot] = (description, sim.model)
            _pose(experiment, sim)
            out[e].append(sim)
    return out


def posed_world_simulations(
    experiments: Sequence[Experiment], worlds: CandidateWorlds
) -> list[list[PosedSimulation]]:
    """Per experiment, per candidate, :func:`posed_simulation`'s state with no compilation.

    One simulation on a host copy of the template is restarted for each candidate and
    experiment (:meth:`~zmpkit.sim.world.Simulation.restart`) with the candidate's fields
    written into the copy (:meth:`~zmpkit.sim.world_fields.WorldFields.write_into`) and its
    description (:meth:`~zmpkit.simfit.candidate_worlds.CandidateWorlds.description_of`:
    its F-T offsets), posed, and frozen (:class:`~zmpkit.sim.posed.PosedSimulation`). The
    posed states and readings are :func:`posed_simulations`'s, bit for bit (tested).
    """
    fields = worlds.fields
    sim = Simulation(worlds.description, seed=0, model=copy.copy(fields.template))
    out: list[list[PosedSimulation]] = [[] for _ in experiments]
    for c in range(len(fields)):
        fields.write_into(sim.model, c)
        description = worlds.description_of(c)
        for e, experiment in enumerate(experiments):
            sim.restart(description, seed=0)
            _pose(experiment, sim)
            out[e].append(PosedSimulation.taken_from(sim))
    return out


def _pose(experiment: Experiment, sim: Simulation) -> None:
    if isinstance(experiment, WalkExperiment):
        start_pose(sim, walk_trajectory(*_walk_key(experiment)))


def _walk_key(experiment: WalkExperiment) -> tuple[Robot, float, float, float, float, str]:
    return (
        experiment.robot,
        experiment.speed_mps,
        experiment.step_duration_s,
        experiment.duration_s,
        experiment.com_height_m,
        experiment.effects or "all",
    )


def open_loop_schedule(experiment: Experiment, sim: StartedSimulation) -> OpenLoopSchedule:
    """The servo setpoints [rad] of ``experiment`` for every physics step of ``sim``.

    Raises:
        ParameterError: on an experiment with no schedule (:func:`is_open_loop`).
    """
    if isinstance(experiment, ShootingWindow):
        raise ParameterError(f"{experiment.name} starts from a measured state: no schedule")
    if isinstance(experiment, WalkExperiment):
        return _walk_schedule(experiment, sim)
    return _step_schedule(experiment, sim)


_WALK_SCHEDULES: dict[tuple, OpenLoopSchedule] = {}
"""Walk schedules of this process, by plan, joints, servo and timestep (a few MB each)."""
_MAX_WALK_SCHEDULES = 16


def _walk_schedule(experiment: WalkExperiment, sim: StartedSimulation) -> OpenLoopSchedule:
    """The frames of :func:`~zmpkit.experiments.walk_trial.simulate_walk`, through the servo.

    The same for every candidate and generation, so computed once (Python per step).
    """
    key = (
        _walk_key(experiment),
        experiment.signals.joint_names,
        sim.joint_names,
        sim.robot.servo_limits,
        sim.dt,
    )
    if key not in _WALK_SCHEDULES:
        if len(_WALK_SCHEDULES) >= _MAX_WALK_SCHEDULES:
            _WALK_SCHEDULES.clear()
        _WALK_SCHEDULES[key] = _plan_walk_schedule(experiment, sim)
    return _recorded_rows(_WALK_SCHEDULES[key], experiment.signals.time_s.size)


def _recorded_rows(schedule: OpenLoopSchedule, rows: int) -> OpenLoopSchedule:
    """``schedule`` up to its ``rows``-th row (a fallen walk's recording ends before its plan)."""
    if rows >= len(schedule.record_steps):
        return schedule
    steps = schedule.record_steps[:rows]
    return OpenLoopSchedule(
        schedule.setpoints_rad[: int(steps[-1]) - schedule.start_step],
        schedule.start_step,
        steps,
        schedule.q_cmd_rad[:rows],
    )


def _plan_walk_schedule(experiment: WalkExperiment, sim: StartedSimulation) -> OpenLoopSchedule:

    trajectory = walk_trajectory(*_walk_key(experiment))
    columns = [trajectory.joint_names.index(j) for j in sim.joint_names]
    frames = trajectory.q_rad[:, columns]
    substeps = max(1, round(float(trajectory.time_s[1] - trajectory.time_s[0]) / sim.dt))
    servo = copy.deepcopy(sim.servo)
    setpoints = np.empty(((len(frames) - 1) * substeps, len(columns)))
    row = 0
    for k in range(1, len(frames)):
        step = (frames[k] - frames[k - 1]) / substeps
        for i in range(1, substeps + 1):
            servo.set_target((frames[k - 1] + i * step).tolist())
            setpoints[row] = servo.tick()
            row += 1
    keep = [sim.joint_names.index(j) for j in experiment.signals.joint_names]
    start = 1  # start_pose took one step
    return OpenLoopSchedule(
        setpoints, start, start + substeps * np.arange(len(frames)), frames[:, keep]
    )


def _step_schedule(experiment: StepExperiment, sim: StartedSimulation) -> OpenLoopSchedule:
    """The recorded setpoints, one per servo tick, sampled at the recorded times."""
    signals = experiment.signals
    if tuple(sim.joint_names) != tuple(signals.joint_names):
        title = experiment.robot.title
        raise SimulationDivergedError(
            0.0, "the joint list", f"recorded joints differ from {title}'s"
        )
    ticks = np.round(signals.time_s / sim.dt).astype(np.int64)
    table = setpoint_table(signals, int(ticks[-1]), sim.dt)
    return OpenLoopSchedule(table, 0, ticks, signals.q_cmd_rad)
