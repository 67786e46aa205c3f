"""Many candidates of one experiment at once: open-loop rollouts on MuJoCo's thread pool.

Both kinds of experiment are open loop (:mod:`~zmpkit.simfit.open_loop`), so the
rollouts of a whole CMA-ES generation run in C on :class:`mujoco.batch.Batch` threads, a
second of simulated time per call, with no Python per physics step; Python then reads the
recorded rows (:mod:`~zmpkit.simfit.batch_rows`) as
:mod:`~zmpkit.simfit.rollout` reads the simulation step by step.

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
  :mod:`~zmpkit.experiments.walk_trial`; its record ends at that frame.

A candidate whose simulation raises another MuJoCo warning (which stops it in the batch but
not in the serial path) is re-run on the serial path.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

import mujoco
import mujoco.batch
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.sim.sensing import sample_series
from zmpkit.sim.solver_settings import SolverSettings
from zmpkit.sim.world import DIVERGED_SPEED_RAD_S, Simulation
from zmpkit.simfit.batch_rows import BatchRows
from zmpkit.simfit.cost import CostTerms, experiment_cost, experiment_cost_of_parts
from zmpkit.simfit.cost_columns import CostColumns, cost_columns, joint_square_error
from zmpkit.simfit.experiments import Experiment
from zmpkit.simfit.open_loop import OpenLoopSchedule, open_loop_schedule, posed_simulations
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import RobotTruth

__all__ = [
    "CHUNK_S",
    "WARP_RECORDS",
    "costs_batches_warp",
    "simulate_batch",
    "simulate_batches",
    "simulate_batches_warp",
]

CHUNK_S = 1.0
"""Simulated time per batch call [s]: fallen and diverged candidates drop out between calls."""
WARP_RECORDS = ("qpos", "sensordata", "site_xpos", "site_xmat")
"""What the signals read of each row on MuJoCo Warp (the rest stays on the device)."""
_TIME = mujoco.mjtState.mjSTATE_TIME
_INTEGRATION = mujoco.mjtState.mjSTATE_INTEGRATION
_BADQACC = int(mujoco.mjtWarning.mjWARN_BADQACC)
_LAYOUT_SIZES = (
    "nq", "nv", "na", "nu", "nbody", "njnt", "ngeom", "nsite", "ntendon", "neq",
    "nsensordata", "nwrap", "nmocap",
)  # fmt: skip


def simulate_batch(
    experiment: Experiment,
    truths: Sequence[RobotTruth],
    effects: str,
    nthread: int = 2,
    warp_device: str | None = None,
) -> list[RecordedSignals]:
    """The signals each candidate's simulator records in ``experiment``.

    Args:
        experiment: the recorded experiment to replay.
        truths: one truth object per candidate (the experiment's robot's).
        effects: effect letters switched on, e.g. ``"M,G"``.
        nthread: threads of the batch (the cores to use).
        warp_device: roll out on MuJoCo Warp on this device (``"cuda:0"``; ``"cpu"`` for
            testing; ``""`` for Warp's default) instead of the CPU batch: float32 physics,
            so close to the serial path but not bit for bit, and only models MuJoCo Warp
            supports (the M effect on).

    Returns:
        Per candidate, what :func:`~zmpkit.simfit.rollout.simulate_experiment`
        returns for it (with ``warp_device``, its float32 approximation).
    """
    if not truths:
        return []
    if warp_device is not None:
        return simulate_batches_warp([experiment], truths, effects, warp_device)[0]
    return _simulate_posed(
        experiment, truths, posed_simulations([experiment], truths, effects)[0], effects, nthread
    )


def simulate_batches(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth],
    effects: str,
    nthread: int = 2,
) -> list[list[RecordedSignals]]:
    """Per experiment, :func:`simulate_batch` of it: each candidate's model compiled once.

    The same signals, bit for bit; a candidate's experiments start from copies of one
    compiled model (:func:`~zmpkit.simfit.open_loop.posed_simulations`).
    """
    if not truths:
        return [[] for _ in experiments]
    posed = posed_simulations(experiments, truths, effects)
    return [
        _simulate_posed(experiment, truths, sims, effects, nthread)
        for experiment, sims in zip(experiments, posed, strict=True)
    ]


def _simulate_posed(
    experiment: Experiment,
    truths: Sequence[RobotTruth],
    sims: Sequence[Simulation],
    effects: str,
    nthread: int,
) -> list[RecordedSignals]:
    """:func:`simulate_batch` from the candidates' posed simulations."""
    schedule = open_loop_schedule(experiment, sims[0])
    out: list[RecordedSignals | None] = [None] * len(sims)
    for group in _layout_groups(sims):
        rows = BatchRows(experiment, [sims[i] for i in group], schedule)
        _run(rows, [sims[i] for i in group], schedule, nthread)
        for i, j in enumerate(group):
            if rows.rerun[i]:
                out[j] = simulate_experiment(experiment, truths[j], effects)
            else:
                out[j] = rows.signals(i)
    return [s for s in out if s is not None]


def simulate_batches_warp(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth],
    effects: str,
    device: str,
    solver: SolverSettings | None = None,
) -> list[list[RecordedSignals]]:
    """Every candidate in every experiment, all in one MuJoCo Warp batch (per model layout).

    A world per (experiment, candidate): each experiment's controls are one sequence of
    the batch (a shorter one holds its last row until the longest ends), each world
    starts from its experiment's pose, and each experiment reads its own rows.

    Args:
        experiments: the recorded experiments to replay (of one robot).
        truths: one truth object per candidate.
        effects: effect letters switched on, e.g. ``"M,G,S"``.
        device: the Warp device (``"cuda:0"``; ``"cpu"`` for testing; ``""`` for Warp's
            default).
        solver: constraint-solver settings for the batch (after the pose); None keeps the
            models' own.

    Returns:
        Per experiment, per candidate, the float32 approximation of what
        :func:`~zmpkit.simfit.rollout.simulate_experiment` returns.
    """

    def signals(part: _WarpPart, i: int, c: int) -> RecordedSignals:
        experiment = experiments[part.experiment]
        if part.rows.rerun[i]:
            return simulate_experiment(experiment, truths[c], effects)
        return part.rows.signals(i)

    return _warp_batches(experiments, truths, effects, device, signals, False, solver)


def costs_batches_warp(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth],
    effects: str,
    device: str,
    keep_zmp_mean: bool = False,
    solver: SolverSettings | None = None,
) -> list[list[CostTerms]]:
    """The cost terms of every candidate in every experiment, from one MuJoCo Warp batch.

    The batch of :func:`simulate_batches_warp`, recording only what the cost reads
    (:mod:`~zmpkit.simfit.cost_columns`): the joint term is summed per world on the
    device, the ZMP and spectrum terms computed here from the few columns recorded. The
    terms are those of :func:`~zmpkit.simfit.cost.experiment_cost` on
    :func:`simulate_batches_warp`'s signals, to float64 rounding (tested).

    Args:
        experiments: the recorded experiments to replay (of one robot).
        truths: one truth object per candidate.
        effects: effect letters switched on, e.g. ``"M,G,S"``.
        device: the Warp device (``"cuda:0"``; ``"cpu"`` for testing; ``""`` for Warp's
            default).
        keep_zmp_mean: charge the mean ZMP difference too (:mod:`~zmpkit.simfit.cost`).
        solver: constraint-solver settings for the batch (after the pose); None keeps the
            models' own.

    Returns:
        Per experiment, per candidate, the cost terms.
    """

    def cost(part: _WarpPart, i: int, c: int) -> CostTerms:
        experiment = experiments[part.experiment]
        if part.rows.rerun[i]:
            simulated = simulate_experiment(experiment, truths[c], effects)
            return experiment_cost(experiment.signals, simulated, keep_zmp_mean)
        zmp, tilt = part.rows.zmp_and_tilt(i)
        square = part.rows.posed_square[i] + part.square[i]
        return experiment_cost_of_parts(
            experiment.signals, len(tilt), square, zmp, tilt, keep_zmp_mean
        )

    return _warp_batches(experiments, truths, effects, device, cost, True, solver)


_Out = TypeVar("_Out")


def _warp_batches(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth],
    effects: str,
    device: str,
    result: Callable[[_WarpPart, int, int], _Out],
    on_device: bool,
    solver: SolverSettings | None,
) -> list[list[_Out]]:
    """Every (experiment, candidate) in one batch per model layout; ``result`` of each.

    ``result(part, i, c)``: the output of the part's ``i``-th world, candidate ``c``;
    ``on_device``: record only the cost's columns and sum the joint term on the device;
    ``solver``: set on every posed model.
    """
    if not truths or not experiments:
        return [[] for _ in experiments]
    parts = []
    for experiment, sims in zip(
        experiments, posed_simulations(experiments, truths, effects), strict=True
    ):
        if solver is not None:
            for sim in sims:
                solver.apply(sim.model)
        parts.append((experiment, sims, open_loop_schedule(experiment, sims[0])))
    worlds = [(e, c) for e in range(len(parts)) for c in range(len(truths))]
    out: list[list[_Out | None]] = [[None] * len(truths) for _ in parts]
    for group in _layout_groups([parts[e][1][c] for e, c in worlds]):
        chosen = [worlds[w] for w in group]
        columns = cost_columns(parts[chosen[0][0]][1][chosen[0][1]]) if on_device else None
        runs = []
        for e, (experiment, sims, schedule) in enumerate(parts):
            mine = [c for f, c in chosen if f == e]
            if mine:
                rows = BatchRows(experiment, [sims[c] for c in mine], schedule, columns)
                runs.append(_WarpPart(rows, [sims[c] for c in mine], schedule, e, mine))
        _run_warp(runs, device, columns)
        for run in runs:
            for i, c in enumerate(run.candidates):
                out[run.experiment][c] = result(run, i, c)
    return [[s for s in per if s is not None] for per in out]


def _layout_groups(sims: Sequence[Simulation]) -> list[list[int]]:
    """Candidates whose models give MjData the same layout (one batch each)."""
    groups: dict[tuple[int, ...], list[int]] = {}
    for i, sim in enumerate(sims):
        key = tuple(getattr(sim.model, size) for size in _LAYOUT_SIZES)
        groups.setdefault(key, []).append(i)
    return list(groups.values())


def _run(
    rows: BatchRows, sims: Sequence[Simulation], schedule: OpenLoopSchedule, nthread: int
) -> None:
    """Roll every candidate out chunk by chunk, filling ``rows``."""
    n = len(sims)
    model0 = sims[0].model
    start = schedule.start_step
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
        measured = _ft_samples(rows, sims, alive, out["sensordata"][:, ft_rows])
        warned = batch.warning[alive, :, 1] != before
        _read_candidates(rows, alive, out, steps, ft_rows, measured, warned, t0, dt)


def _read_candidates(
    rows: BatchRows,
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
        rows: what each candidate records; filled, and its done/rerun/diverged flags set.
        alive: the candidates (indices into ``rows``) simulated in this chunk.
        out: the chunk's records, ``(alive, rows, ...)`` per item (``qvel`` optional when
            ``valid`` covers the speeds).
        steps: the step each recorded row ends (every step, or, on MuJoCo Warp, those the
            signals read).
        ft_rows: the rows that are F-T sample steps.
        measured: the F-T readings at those samples, (alive, samples, feet, 6).
        warned: per alive candidate, which MuJoCo warnings rose in the chunk.
        t0: each candidate's time at the start [s].
        dt: the physics time step [s].
        valid: rows each candidate's engine vouches for (MuJoCo Warp), or None.
    """
    start = rows.schedule.start_step
    for a, i in enumerate(alive):
        if np.delete(warned[a], _BADQACC).any():
            rows.rerun[i] = rows.done[i] = True
            continue
        expected = t0[i] + (steps - start) * dt
        bad = np.flatnonzero(np.abs(out["time"][a, :, 0] - expected) > 0.5 * dt)
        fast = ft_rows[:0]  # MuJoCo Warp checks the speeds itself (``valid``)
        if "qvel" in out:
            speed = out["qvel"][a, ft_rows]
            fast = ft_rows[~np.all(np.abs(speed) <= DIVERGED_SPEED_RAD_S, axis=1)]
        limit = min(bad[0] if len(bad) else len(steps), fast[0] if len(fast) else len(steps))
        if valid is not None:
            limit = min(limit, int(valid[a]))
        rows.read_chunk(i, {k: v[a] for k, v in out.items()}, steps, ft_rows, measured[a], limit)
        flagged = warned[a, _BADQACC] and limit == len(steps)
        if (limit < len(steps) or flagged) and not rows.done[i]:
            rows.diverged[i] = rows.done[i] = True


@dataclass(frozen=True)
class _WarpPart:
    """One experiment's candidates in a MuJoCo Warp batch.

    Attributes:
        rows: what each of them records (filled by :func:`_run_warp`).
        sims: their posed simulations.
        schedule: the experiment's open-loop schedule.
        experiment: the experiment's index.
        candidates: their indices among the candidates.
    """

    rows: BatchRows
    sims: Sequence[Simulation]
    schedule: OpenLoopSchedule
    experiment: int
    candidates: list[int]
    square: list[float] = field(default_factory=list)
    """Per world, the joint term's sum over the rollout's rows, from the device [rad²]."""

    def kept_steps(self, ft_samples: bool = True) -> NDArray[np.int64]:
        """The rollout steps the signals read (1 is the first).

        The recorded frames, the F-T sample steps (``ft_samples``: needed only when the
        sensor effect samples them) and the last step (a divergence up to the end still
        counts, as when every step was kept).
        """
        start = self.schedule.start_step
        nstep = len(self.schedule.setpoints_rad)
        steps = start + np.arange(1, nstep + 1)
        keep = np.isin(steps, self.schedule.record_steps)
        if ft_samples:
            keep |= steps % self.sims[0].ft_sample_every == 0
        keep[-1] = True
        return np.flatnonzero(keep) + 1

    def target_rows(self) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
        """The rollout steps of the recorded rows after the posed one, and their encoders."""
        record = self.schedule.record_steps
        after = record > self.schedule.start_step
        return record[after] - self.schedule.start_step, self.rows.experiment.signals.q_meas_rad[
            after
        ]


def _run_warp(parts: Sequence[_WarpPart], device: str, columns: CostColumns | None) -> None:
    """Roll every part's candidates out on MuJoCo Warp in one batch, filling their rows.

    Only the rows the signals read are recorded, on the device, with ``qpos``,
    ``sensordata`` and the site kinematics (which lag one step, as after ``mj_step``), or,
    with ``columns``, only those columns, the joint term summed on the device into each
    part's ``square``; MuJoCo Warp checks every step for divergence.
    """
    from zmpkit.sim.warp_batch import rollout_warp

    controls = []
    for part in parts:
        mine = part.sims[0].controls_of(part.schedule.setpoints_rad)
        if any(
            not np.array_equal(s.controls_of(part.schedule.setpoints_rad), mine) for s in part.sims
        ):
            raise ParameterError(
                "the Warp backend needs the same actuator gears in every candidate"
            )
        controls.append(mine)
    longest = max(len(c) for c in controls)
    table = np.stack(
        [np.concatenate([c, np.repeat(c[-1:], longest - len(c), 0)]) for c in controls]
    )
    sims = [s for part in parts for s in part.sims]
    group = np.repeat(np.arange(len(parts)), [len(part.sims) for part in parts])
    full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    initial = np.empty((len(sims), mujoco.mj_stateSize(sims[0].model, full)))
    for i, sim in enumerate(sims):
        mujoco.mj_getState(sim.model, sim.data, initial[i], full)
    ft_samples = columns is None or any(any(part.rows.sensors) for part in parts)
    kept = [part.kept_steps(ft_samples) for part in parts]
    record_steps = np.unique(np.concatenate(kept))
    square = None
    if columns is not None:
        targets = [part.target_rows() for part in parts]
        square = joint_square_error(
            [part.sims[0] for part in parts],
            [part.rows.experiment.signals.joint_names for part in parts],
            [steps for steps, _ in targets],
            [rows for _, rows in targets],
        )
    result = rollout_warp(
        [s.model for s in sims],
        initial,
        table,
        device=device or None,
        record_steps=record_steps,
        record=WARP_RECORDS,
        control_group=group,
        columns=None if columns is None else columns.as_mapping(),
        square_error=square,
    )
    nsite = sims[0].model.nsite if columns is None else len(columns.sites)
    first = 0
    for part, steps_kept in zip(parts, kept, strict=True):
        worlds = slice(first, first + len(part.sims))
        first = worlds.stop
        if result.square_error is not None:
            part.square.extend(result.square_error[worlds].tolist())
        rows_of_part = np.flatnonzero(np.isin(result.steps, steps_kept))
        n, nrec = len(part.sims), len(rows_of_part)

        picked = {name: result.records[name][worlds][:, rows_of_part] for name in WARP_RECORDS}
        steps = part.schedule.start_step + result.steps[rows_of_part]
        ft_rows = np.flatnonzero(steps % part.sims[0].ft_sample_every == 0)
        out = {
            "time": result.time[worlds][:, rows_of_part, None],
            "qpos": picked["qpos"],
            "sensordata": picked["sensordata"],
            "site_xpos": picked["site_xpos"].reshape(n, nrec, nsite, 3),
            "site_xmat": picked["site_xmat"].reshape(n, nrec, nsite, 9),
        }
        valid = np.searchsorted(rows_of_part, result.valid_rows[worlds], side="left")
        alive = list(range(n))
        measured = _ft_samples(part.rows, part.sims, alive, out["sensordata"][:, ft_rows])
        warned = np.zeros((n, int(mujoco.mjtWarning.mjNWARNING)), dtype=bool)
        t0 = initial[worlds, 0]
        _read_candidates(
            part.rows, alive, out, steps, ft_rows, measured, warned, t0, part.sims[0].dt, valid
        )


def _ft_samples(
    rows: BatchRows, sims: Sequence[Simulation], alive: list[int], sensordata: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The F-T readings at the chunk's sample steps, (alive, samples, feet, 6).

    Args:
        rows: what each candidate records (its feet, and which have the sensor effect on).
        sims: every candidate's simulation (its F-T channels).
        alive: the candidates (indices into ``sims``) simulated in this chunk.
        sensordata: MuJoCo's sensor rows at those steps, (alive, samples, nsensordata).
    """
    wrenches = rows.ft_true(sensordata)
    noisy = [a for a, i in enumerate(alive) if rows.sensors[i]]
    if not noisy:
        return wrenches
    out = wrenches.copy()
    # Every foot's channels in one series, foot by foot as the channels were drawn before.
    channels = [sims[alive[a]].ft_channel(f) for f in rows.feet for a in noisy]
    nfeet, nnoisy, nsample = len(rows.feet), len(noisy), wrenches.shape[1]
    feet_first = np.moveaxis(wrenches[noisy], 2, 0).reshape(nfeet * nnoisy, nsample, 6)
    with np.errstate(invalid="ignore", over="ignore"):
        sampled = sample_series(channels, feet_first)
    out[noisy] = np.moveaxis(sampled.reshape(nfeet, nnoisy, nsample, 6), 0, 2)
    return out
