"""Many candidates of one experiment at once: open-loop rollouts on MuJoCo's thread pool.

Both kinds of experiment are open loop. A walk plays its planned frames through the servo
(no controller reads a sensor), a step trial plays its recorded setpoints; so the servo
setpoints of every physics step are known before the rollout starts, and they are the same
for every candidate (candidates differ in the model, not in the command). The rollouts of
a whole CMA-ES generation then run in C on :class:`mujoco.batch.Batch` threads, a second of
simulated time per call, with no Python per physics step; Python reads the recorded rows
afterwards, as :mod:`~zmpkit.identify.simfit.rollout` reads the simulation step by step.

The results are those of the serial path (tested): each candidate's
:class:`~zmpkit.sim.world.Simulation` is built and posed as there, the batch continues from
its exact integration state (warm start included), the F-T channels draw the same noise
(:func:`~zmpkit.sim.sensing.sample_series`), and a fall or a divergence ends a rollout at
the same step:

- divergence: MuJoCo's bad-acceleration warning (the batch stops that simulation, so its
  time stops advancing) or a joint speed beyond
  :data:`~zmpkit.sim.world.DIVERGED_SPEED_RAD_S` at an F-T sample; a walk then has no
  signals, a step trial keeps the samples before it;
- a walk's fall: trunk tilt or torso height past the limits of
  :mod:`~zmpkit.pipelines.walk_sim`; its record ends at that frame.

A candidate whose simulation raises another MuJoCo warning (which stops it in the batch but
not in the serial path) is re-run on the serial path.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import mujoco.batch
import numpy as np
from numpy.typing import NDArray

from zmpkit.identify.simfit.experiments import (
    Experiment,
    RecordedSignals,
    StepExperiment,
    WalkExperiment,
)
from zmpkit.identify.simfit.rollout import (
    empty_signals,
    setpoint_table,
    simulate_experiment,
    step_signals,
)
from zmpkit.sim.sensing import sample_series
from zmpkit.sim.world import DIVERGED_SPEED_RAD_S, Simulation

__all__ = ["CHUNK_S", "OpenLoopSchedule", "simulate_batch"]

CHUNK_S = 1.0
"""Simulated time per batch call [s]: fallen and diverged candidates drop out between calls."""
_TIME = mujoco.mjtState.mjSTATE_TIME
_INTEGRATION = mujoco.mjtState.mjSTATE_INTEGRATION
_BADQACC = int(mujoco.mjtWarning.mjWARN_BADQACC)


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


def simulate_batch(
    experiment: Experiment,
    truths: Sequence[object],
    effects: str,
    nthread: int = 2,
    warp_device: str | None = None,
) -> list[RecordedSignals]:
    """The signals each candidate's simulator records in ``experiment``.

    Args:
        experiment: the recorded experiment to replay.
        truths: one truth object per candidate (``NaoTruth`` or ``TeoTruth``).
        effects: effect letters switched on, e.g. ``"M,G"``.
        nthread: threads of the batch (the cores to use).
        warp_device: roll out on MuJoCo Warp on this device (``"cuda:0"``; ``"cpu"`` for
            testing; ``""`` for Warp's default) instead of the CPU batch: float32 physics,
            so close to the serial path but not bit for bit, and only models MuJoCo Warp
            supports (the M effect on).

    Returns:
        Per candidate, what :func:`~zmpkit.identify.simfit.rollout.simulate_experiment`
        returns for it (with ``warp_device``, its float32 approximation).
    """
    if not truths:
        return []
    sims = [_posed(experiment, truth, effects) for truth in truths]
    schedule = _schedule(experiment, sims[0])
    out: list[RecordedSignals | None] = [None] * len(sims)
    for group in _layout_groups(sims):
        rows = _Rows(experiment, [sims[i] for i in group], schedule)
        if warp_device is None:
            _run(rows, [sims[i] for i in group], schedule, nthread)
        else:
            _run_warp(rows, [sims[i] for i in group], schedule, warp_device)
        for i, j in enumerate(group):
            if rows.rerun[i]:
                out[j] = simulate_experiment(experiment, truths[j], effects)
            else:
                out[j] = rows.signals(i)
    return [s for s in out if s is not None]


def _posed(experiment: Experiment, truth: object, effects: str) -> Simulation:
    """A candidate's simulation where the serial path starts its loop."""
    if isinstance(experiment, WalkExperiment):
        from zmpkit.identify.simfit.walk_plan import walk_trajectory
        from zmpkit.pipelines.walk_sim import start_pose
        from zmpkit.robots.nao import make_nao

        sim = make_nao(effects, truth, seed=0)  # type: ignore[arg-type]
        start_pose(sim, walk_trajectory(*_walk_key(experiment)))
        return sim
    from zmpkit.robots.teo import make_teo

    return make_teo(effects, truth, seed=0)  # type: ignore[arg-type]


def _walk_key(experiment: WalkExperiment) -> tuple[float, float, float, float]:
    return (
        experiment.speed_mps,
        experiment.step_duration_s,
        experiment.duration_s,
        experiment.com_height_m,
    )


def _schedule(experiment: Experiment, sim: Simulation) -> OpenLoopSchedule:
    if isinstance(experiment, WalkExperiment):
        return _walk_schedule(experiment, sim)
    return _step_schedule(experiment, sim)


_WALK_SCHEDULES: dict[tuple, OpenLoopSchedule] = {}
"""Walk schedules of this process, by plan, joints, servo and timestep (a few MB each)."""
_MAX_WALK_SCHEDULES = 16


def _walk_schedule(experiment: WalkExperiment, sim: Simulation) -> OpenLoopSchedule:
    """The frames of :func:`~zmpkit.pipelines.walk_sim.simulate_walk`, through the servo.

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
    return _WALK_SCHEDULES[key]


def _plan_walk_schedule(experiment: WalkExperiment, sim: Simulation) -> OpenLoopSchedule:
    from zmpkit.identify.simfit.walk_plan import walk_trajectory

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


def _step_schedule(experiment: StepExperiment, sim: Simulation) -> OpenLoopSchedule:
    """The recorded setpoints, one per servo tick, sampled at the recorded times."""
    from zmpkit.errors import SimulationDivergedError

    signals = experiment.signals
    if tuple(sim.joint_names) != tuple(signals.joint_names):
        raise SimulationDivergedError(0.0, "the joint list", "recorded joints differ from TEO's")
    ticks = np.round(signals.time_s / sim.dt).astype(np.int64)
    table = setpoint_table(signals, int(ticks[-1]), sim.dt)
    return OpenLoopSchedule(table, 0, ticks, signals.q_cmd_rad)


def _layout_groups(sims: Sequence[Simulation]) -> list[list[int]]:
    """Candidates whose models give MjData the same layout (one batch each)."""
    groups: dict[tuple[int, ...], list[int]] = {}
    for i, sim in enumerate(sims):
        m = sim.model
        key = (m.nq, m.nv, m.na, m.nu, m.nbody, m.njnt, m.ngeom, m.nsite, m.ntendon, m.neq)
        groups.setdefault((*key, m.nsensordata, m.nwrap, m.nmocap), []).append(i)
    return list(groups.values())


class _Rows:
    """What each candidate records, filled chunk by chunk: a list of row blocks each."""

    def __init__(
        self, experiment: Experiment, sims: Sequence[Simulation], schedule: OpenLoopSchedule
    ) -> None:
        self.experiment, self.sims, self.schedule = experiment, sims, schedule
        self.walk = isinstance(experiment, WalkExperiment)
        sim = sims[0]
        self.feet = tuple(f.foot for f in sim.robot.feet)
        self.ft_sites = [sim.model.site(f.site).id for f in sim.robot.feet]
        self.quat = sim.sensor_slice(sim.robot.imu.orientation)
        self.sensors = [s.robot.effects.sensors for s in sims]
        n = len(sims)
        self.done = [False] * n
        self.rerun = [False] * n
        self.diverged = [False] * n
        self.blocks: list[list[dict[str, NDArray[np.float64]]]] = [[] for _ in range(n)]
        self.ft_now = [np.array([s.ft_channel(f).output for f in self.feet]) for s in sims]

    def read_posed(self, i: int) -> None:
        """The row of the posed state (a walk's frame 0; the serial path checks no fall)."""
        data = self.sims[i].data
        block = {
            "qpos": data.qpos[None].copy(),
            "sensordata": data.sensordata[None].copy(),
            "time": np.array([data.time]),
            "site_xpos": data.site_xpos[None, self.ft_sites].copy(),
            "site_xmat": data.site_xmat[None, self.ft_sites].copy(),
        }
        block["ft"] = self._ft(i, block["sensordata"], self.ft_now[i][None])
        self.blocks[i].append(block)

    def _ft(
        self, i: int, sensordata: NDArray[np.float64], sampled: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """F-T readings (rows, feet, 6): the last samples (S on) or the true wrench."""
        if self.sensors[i]:
            return sampled
        sim = self.sims[i]
        return np.stack([sim.ft_true_of(f, sensordata) for f in self.feet], axis=1)

    def read_chunk(
        self,
        i: int,
        rows: dict[str, NDArray[np.float64]],
        steps: NDArray[np.int64],
        ft_rows: NDArray[np.int64],
        sampled: NDArray[np.float64],
        limit: int,
    ) -> None:
        """Keep candidate ``i``'s rows among a chunk's first ``limit`` steps.

        Args:
            rows: the chunk's records of this candidate, one row per step.
            steps: the step each row ends.
            ft_rows: the rows that are F-T sample steps.
            sampled: the F-T readings of those samples, (len(ft_rows), feet, 6).
            limit: rows from here on are past a divergence.
        """
        wanted = np.flatnonzero(np.isin(steps[:limit], self.schedule.record_steps))
        if self.walk:
            fall = _first_fall(rows["qpos"][wanted], rows["sensordata"][wanted, self.quat])
            if fall is not None:
                wanted = wanted[: fall + 1]
                self.done[i] = True
        last = np.searchsorted(ft_rows, wanted, side="right") - 1
        held = np.concatenate([self.ft_now[i][None], sampled])[last + 1]
        block = {
            "qpos": rows["qpos"][wanted],
            "sensordata": rows["sensordata"][wanted],
            "time": rows["time"][wanted, 0],
            "site_xpos": rows["site_xpos"][wanted][:, self.ft_sites],
            "site_xmat": rows["site_xmat"][wanted][:, self.ft_sites],
        }
        block["ft"] = self._ft(i, block["sensordata"], held)
        self.blocks[i].append(block)
        taken = np.searchsorted(ft_rows, limit) - 1
        if taken >= 0:
            self.ft_now[i] = sampled[taken]

    def signals(self, i: int) -> RecordedSignals:
        """The candidate's recorded signals."""
        signals, blocks = self.experiment.signals, self.blocks[i]
        if not blocks or (self.walk and self.diverged[i]):
            return empty_signals(signals)
        rows = {k: np.concatenate([b[k] for b in blocks]) for k in blocks[0]}
        n = len(rows["time"])
        if n == 0:
            return empty_signals(signals)
        sim = self.sims[i]
        encoders = sim.encoders_of(rows["qpos"])
        quats = rows["sensordata"][:, self.quat]
        if not self.walk:
            right, left = (rows["ft"][:, self.feet.index(f)] for f in ("right", "left"))
            data = np.concatenate([right, left, encoders, quats], axis=1)
            return step_signals(self.experiment, data, n)  # type: ignore[arg-type]
        from zmpkit.analysis.walk_metrics import measured_zmp
        from zmpkit.identify.simfit.experiments import tilt_from_quaternions
        from zmpkit.pipelines.walk_sim import wrench_in_world

        force, moment = wrench_in_world(rows["site_xmat"], rows["ft"])
        keep = [sim.joint_names.index(j) for j in signals.joint_names]
        return RecordedSignals(
            rows["time"],
            signals.joint_names,
            self.schedule.q_cmd_rad[:n],
            encoders[:, keep],
            measured_zmp(force, moment, rows["site_xpos"]),
            tilt_from_quaternions(quats, "sagittal"),
        )


def _first_fall(qpos: NDArray[np.float64], quat: NDArray[np.float64]) -> int | None:
    """The first row where the serial path's fall rule fires, or None.

    Screened with numpy, decided with the serial path's own scalar rule (so a tilt within
    rounding of the limit is judged exactly as there).
    """
    from zmpkit.pipelines.walk_sim import FALL_TILT_RAD, FALL_TORSO_HEIGHT_M, quaternion_pitch_roll

    w, x, y, z = quat.T
    pitch = np.arcsin(np.clip(2.0 * (w * y - z * x), -1.0, 1.0))
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    margin = 1e-9
    near = np.maximum(np.abs(pitch), np.abs(roll)) > FALL_TILT_RAD - margin
    near |= qpos[:, 2] < FALL_TORSO_HEIGHT_M + margin
    for r in np.flatnonzero(near):
        p, q = quaternion_pitch_roll(quat[r])
        if max(abs(p), abs(q)) > FALL_TILT_RAD or float(qpos[r, 2]) < FALL_TORSO_HEIGHT_M:
            return int(r)
    return None


def _run(rows: _Rows, sims: Sequence[Simulation], schedule: OpenLoopSchedule, nthread: int) -> None:
    """Roll every candidate out chunk by chunk, filling ``rows``."""
    n = len(sims)
    model0 = sims[0].model
    start = schedule.start_step
    for i in range(n):
        if schedule.record_steps[0] == start:
            rows.read_posed(i)
    batch = mujoco.batch.Batch(model0, n, nthread=nthread)
    if n > 1:
        batch.set_models([s.model for s in sims])
    for i, sim in enumerate(sims):
        mujoco.mj_getState(sim.model, sim.data, batch.state[i], _INTEGRATION)
    controls = np.stack([s.controls_of(schedule.setpoints_rad) for s in sims])
    ft_every = sims[0].ft_sample_every
    t0 = np.array([s.data.time for s in sims])
    dt = sims[0].dt
    chunk = max(1, round(CHUNK_S / dt))
    nstep = len(schedule.setpoints_rad)
    records = ("qpos", "qvel", "sensordata", "site_xpos", "site_xmat", _TIME)
    for c0 in range(0, nstep, chunk):
        alive = [i for i in range(n) if not rows.done[i]]
        if not alive:
            return
        c1 = min(nstep, c0 + chunk)
        before = batch.warning[alive, :, 1].copy()
        out = batch.rollout(c1 - c0, controls[alive, c0:c1], record=records, ids=alive)
        out["time"] = out.pop(_TIME)
        steps = start + np.arange(c0 + 1, c1 + 1)  # the step each recorded row ends
        ft_rows = np.flatnonzero(steps % ft_every == 0)
        wrenches = np.stack(
            [
                np.stack(
                    [sims[i].ft_true_of(f, out["sensordata"][a, ft_rows]) for f in rows.feet], 1
                )
                for a, i in enumerate(alive)
            ]
        )
        measured = _ft_samples(rows, sims, alive, wrenches)
        warned = batch.warning[alive, :, 1] != before
        _read_candidates(rows, alive, out, steps, ft_rows, measured, warned, t0, dt)


def _read_candidates(
    rows: _Rows,
    alive: list[int],
    out: dict,
    steps: NDArray[np.int64],
    ft_rows: NDArray[np.int64],
    measured: NDArray[np.float64],
    warned: NDArray[np.bool_],
    t0: NDArray[np.float64],
    dt: float,
    valid: NDArray[np.int64] | None = None,
) -> None:
    """Judge each alive candidate's rows of a chunk (divergence) and keep the wanted ones.

    Args:
        out: the chunk's records, ``(alive, steps, ...)`` per item.
        warned: per alive candidate, which MuJoCo warnings rose in the chunk.
        t0: each candidate's time at the start [s].
        valid: rows each candidate's engine vouches for (MuJoCo Warp), or None.
    """
    start = rows.schedule.start_step
    for a, i in enumerate(alive):
        if np.delete(warned[a], _BADQACC).any():
            rows.rerun[i] = rows.done[i] = True
            continue
        expected = t0[i] + (steps - start) * dt
        bad = np.flatnonzero(np.abs(out["time"][a, :, 0] - expected) > 0.5 * dt)
        speed = out["qvel"][a, ft_rows]
        fast = ft_rows[~np.all(np.abs(speed) <= DIVERGED_SPEED_RAD_S, axis=1)]
        limit = min(bad[0] if len(bad) else len(steps), fast[0] if len(fast) else len(steps))
        if valid is not None:
            limit = min(limit, int(valid[a]))
        rows.read_chunk(i, {k: v[a] for k, v in out.items()}, steps, ft_rows, measured[a], limit)
        flagged = warned[a, _BADQACC] and limit == len(steps)
        if (limit < len(steps) or flagged) and not rows.done[i]:
            rows.diverged[i] = rows.done[i] = True


def _run_warp(
    rows: _Rows, sims: Sequence[Simulation], schedule: OpenLoopSchedule, device: str
) -> None:
    """Roll every candidate out on MuJoCo Warp at once, filling ``rows``."""
    from zmpkit.errors import ParameterError
    from zmpkit.sim.warp_batch import rollout_warp

    n, model0 = len(sims), sims[0].model
    start = schedule.start_step
    for i in range(n):
        if schedule.record_steps[0] == start:
            rows.read_posed(i)
    controls = sims[0].controls_of(schedule.setpoints_rad)
    if any(not np.array_equal(s.controls_of(schedule.setpoints_rad), controls) for s in sims):
        raise ParameterError("the Warp backend needs the same actuator gears in every candidate")
    full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    initial = np.empty((n, mujoco.mj_stateSize(model0, full)))
    for i, sim in enumerate(sims):
        mujoco.mj_getState(sim.model, sim.data, initial[i], full)
    result = rollout_warp([s.model for s in sims], initial, controls, 1, device or None)
    nq, nv = model0.nq, model0.nv
    nstep = len(controls)
    steps = start + np.arange(1, nstep + 1)
    ft_rows = np.flatnonzero(steps % sims[0].ft_sample_every == 0)
    wanted = np.flatnonzero(np.isin(steps, schedule.record_steps))
    qpos = result.state[:, :, 1 : 1 + nq]
    out = {
        "time": result.state[:, :, :1],
        "qpos": qpos,
        "qvel": result.state[:, :, 1 + nq : 1 + nq + nv],
        "sensordata": result.sensordata,
        "site_xpos": np.zeros((n, nstep, model0.nsite, 3)),
        "site_xmat": np.zeros((n, nstep, model0.nsite, 9)),
    }
    for i, sim in enumerate(sims):  # derived fields lag one step, as after mj_step
        before = np.concatenate([initial[i, None, 1 : 1 + nq], qpos[i, :-1]])
        data = mujoco.MjData(sim.model)
        for r in wanted:
            data.qpos[:] = before[r]
            mujoco.mj_kinematics(sim.model, data)
            out["site_xpos"][i, r], out["site_xmat"][i, r] = data.site_xpos, data.site_xmat
    wrenches = np.stack(
        [
            np.stack([s.ft_true_of(f, result.sensordata[i, ft_rows]) for f in rows.feet], 1)
            for i, s in enumerate(sims)
        ]
    )
    alive = list(range(n))
    measured = _ft_samples(rows, sims, alive, wrenches)
    warned = np.zeros((n, int(mujoco.mjtWarning.mjNWARNING)), dtype=bool)
    t0 = initial[:, 0]
    _read_candidates(
        rows, alive, out, steps, ft_rows, measured, warned, t0, sims[0].dt, result.valid_rows
    )


def _ft_samples(
    rows: _Rows, sims: Sequence[Simulation], alive: list[int], wrenches: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The F-T readings at the chunk's sample steps, (alive, samples, feet, 6).

    Args:
        wrenches: the true wrenches there, same shape.
    """
    noisy = [a for a, i in enumerate(alive) if rows.sensors[i]]
    if not noisy:
        return wrenches
    out = wrenches.copy()
    for k, f in enumerate(rows.feet):
        channels = [sims[alive[a]].ft_channel(f) for a in noisy]
        with np.errstate(invalid="ignore", over="ignore"):
            out[noisy, :, k] = sample_series(channels, wrenches[noisy, :, k])
    return out
