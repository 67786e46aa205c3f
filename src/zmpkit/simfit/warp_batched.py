"""Every candidate in every experiment in one MuJoCo Warp batch (per model layout).

The GPU counterpart of :mod:`~zmpkit.simfit.batched`: a world per (experiment,
candidate), each experiment's controls one sequence of the batch, only the rows the signals
read recorded on the device (:data:`WARP_RECORDS`), or only the columns the cost reads with
the joint term summed on the device (:func:`costs_batches_warp`). Float32 physics: close to
the serial path, not bit for bit; MuJoCo Warp checks every step for divergence, and the rows
are judged as the CPU batch judges them (:mod:`~zmpkit.simfit.batch_reading`).
"""

from __future__ import annotations

import copy
import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypeVar

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.sim.posed import PosedSimulation, StartedSimulation
from zmpkit.sim.solver_settings import SolverSettings
from zmpkit.sim.world_fields import WorldFields
from zmpkit.simfit.batch_reading import ft_readings, layout_groups, read_candidates
from zmpkit.simfit.batch_rows import BatchRows
from zmpkit.simfit.candidate_worlds import CandidateValues, candidate_worlds, field_map_gap
from zmpkit.simfit.cost import CostTerms, experiment_cost, experiment_cost_of_parts
from zmpkit.simfit.cost_columns import CostColumns, cost_columns, joint_square_error
from zmpkit.simfit.experiments import Experiment
from zmpkit.simfit.open_loop import (
    OpenLoopSchedule,
    open_loop_schedule,
    posed_simulations,
    posed_world_simulations,
)
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import RobotTruth

if TYPE_CHECKING:
    from zmpkit.sim.warp_batch import WarpRollout
    from zmpkit.sim.warp_columns import QposSquareError

__all__ = ["WARP_RECORDS", "costs_batches_warp", "field_path_gap", "simulate_batches_warp"]

_LOG = logging.getLogger(__name__)

WARP_RECORDS = ("qpos", "sensordata", "site_xpos", "site_xmat")
"""What the signals read of each row on MuJoCo Warp (the rest stays on the device)."""


def simulate_batches_warp(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth] | CandidateValues,
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
        truths: one truth object per candidate, or the candidates' parameter values
            (:class:`~zmpkit.simfit.candidate_worlds.CandidateValues`): then, where the
            robot's field rule maps every parameter, one compiled model with each
            candidate's fields written per world (:func:`field_path_gap` says when not).
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
            return simulate_experiment(experiment, _truth(truths, c), effects)
        return part.rows.signals(i)

    return _warp_batches(experiments, truths, effects, device, signals, False, solver)


def costs_batches_warp(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth] | CandidateValues,
    effects: str,
    device: str,
    models_loads: bool = False,
    solver: SolverSettings | None = None,
) -> list[list[CostTerms]]:
    """The cost terms of every candidate in every experiment, from one MuJoCo Warp batch.

    The batch of :func:`simulate_batches_warp`, recording only what the cost reads
    (:mod:`~zmpkit.simfit.cost_columns`): the joint term is summed per world on the
    device, the ZMP, force and spectrum terms computed here from the few columns recorded. The
    terms are those of :func:`~zmpkit.simfit.cost.experiment_cost` on
    :func:`simulate_batches_warp`'s signals, to float64 rounding (tested).

    Args:
        experiments: as :func:`simulate_batches_warp`.
        truths: as :func:`simulate_batches_warp`.
        effects: as :func:`simulate_batches_warp`.
        device: as :func:`simulate_batches_warp`.
        models_loads: charge the mean ZMP difference and the feet's forces too
            (:mod:`~zmpkit.simfit.cost`).
        solver: as :func:`simulate_batches_warp`.

    Returns:
        Per experiment, per candidate, the cost terms.
    """

    def cost(part: _WarpPart, i: int, c: int) -> CostTerms:
        experiment = experiments[part.experiment]
        if part.rows.rerun[i]:
            simulated = simulate_experiment(experiment, _truth(truths, c), effects)
            return experiment_cost(experiment.signals, simulated, models_loads)
        zmp, force, tilt = part.rows.cost_readings(i)
        square = part.rows.posed_square[i] + part.square[i]
        return experiment_cost_of_parts(
            experiment.signals, len(tilt), square, zmp, tilt, force, models_loads
        )

    return _warp_batches(experiments, truths, effects, device, cost, True, solver)


_Out = TypeVar("_Out")


def _truth(truths: Sequence[RobotTruth] | CandidateValues, c: int) -> RobotTruth:
    """Candidate ``c``'s truth object (built only for a rerun on the serial path)."""
    return truths.truth(c) if isinstance(truths, CandidateValues) else truths[c]


def field_path_gap(
    experiments: Sequence[Experiment], truths: Sequence[RobotTruth] | CandidateValues
) -> str | None:
    """Why a batch compiles each candidate's MJCF, or None when it writes per-world fields.

    It writes them when the candidates come as parameter values of one robot, every
    experiment is of that robot, and its field rule maps every parameter
    (:func:`~zmpkit.simfit.candidate_worlds.field_map_gap`).
    """
    if not isinstance(truths, CandidateValues):
        return "the candidates come as truth objects, not as parameter values"
    robot = truths.robot
    others = sorted(
        {
            e.robot.title
            for e in experiments
            if e.robot is not robot and e.robot.source != robot.source
        }
    )
    if others:
        return f"experiments of other robots than the fitted one: {others}"
    return field_map_gap(truths.robot, truths.parameters)


@dataclass(frozen=True)
class _Posed:
    """Every candidate posed for every experiment.

    Attributes:
        sims: per experiment, per candidate, its posed simulation.
        worlds: the one compiled model and each candidate's fields (one world per
            candidate, every experiment); None: each simulation's own model.
        reason: why ``worlds`` is None (:func:`field_path_gap`), else empty.
    """

    sims: Sequence[Sequence[StartedSimulation]]
    worlds: WorldFields | None
    reason: str = ""


def _posed(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth] | CandidateValues,
    effects: str,
    solver: SolverSettings | None,
) -> _Posed:
    """The posed candidates: written into one compiled model where it can, else compiled."""
    reason = field_path_gap(experiments, truths)
    if reason is None and isinstance(truths, CandidateValues):
        try:
            worlds = candidate_worlds(truths, effects)
        except ParameterError as exc:  # a truth document the rule cannot map
            reason = str(exc)
        else:
            posed = posed_world_simulations(experiments, worlds)
            fields = worlds.fields
            if solver is not None:  # after the pose, as on the compile path
                template = copy.copy(fields.template)
                solver.apply(template)
                fields = WorldFields(template, fields.values, fields.nworld)
            return _Posed(posed, fields)
    if isinstance(truths, CandidateValues):
        _LOG.info("the Warp batch compiles each candidate's MJCF: %s", reason)
    every = truths.truths() if isinstance(truths, CandidateValues) else list(truths)
    sims = posed_simulations(experiments, every, effects)
    if solver is not None:
        for per in sims:
            for sim in per:
                solver.apply(sim.model)
    return _Posed(sims, None, reason or "")


def _warp_batches(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth] | CandidateValues,
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
    if not len(truths) or not experiments:
        return [[] for _ in experiments]
    posed = _posed(experiments, truths, effects, solver)
    parts: list[tuple[Experiment, Sequence[StartedSimulation], OpenLoopSchedule]] = [
        (experiment, sims, open_loop_schedule(experiment, sims[0]))
        for experiment, sims in zip(experiments, posed.sims, strict=True)
    ]
    ncand = len(truths)
    worlds = [(e, c) for e in range(len(parts)) for c in range(ncand)]
    out: list[list[_Out | None]] = [[None] * ncand for _ in parts]
    for group in layout_groups([parts[e][1][c] for e, c in worlds]):
        chosen = [worlds[w] for w in group]
        columns = cost_columns(parts[chosen[0][0]][1][chosen[0][1]]) if on_device else None
        runs = []
        for e, (experiment, sims, schedule) in enumerate(parts):
            mine = [c for f, c in chosen if f == e]
            if mine:
                rows = BatchRows(experiment, [sims[c] for c in mine], schedule, columns)
                runs.append(_WarpPart(rows, [sims[c] for c in mine], schedule, e, mine))
        _run_warp(runs, device, columns, _group_models(runs, posed.worlds))
        for run in runs:
            for i, c in enumerate(run.candidates):
                out[run.experiment][c] = result(run, i, c)
    return [[s for s in per if s is not None] for per in out]


def _group_models(
    runs: Sequence[_WarpPart], worlds: WorldFields | None
) -> list[mujoco.MjModel] | WorldFields:
    """The models of a batch's worlds: each simulation's own, or rows of ``worlds``."""
    if worlds is None:
        return [s.model for run in runs for s in run.sims]
    rows = np.concatenate([np.asarray(run.candidates, dtype=np.int64) for run in runs])
    values = {name: stack[rows] for name, stack in worlds.values.items()}
    return WorldFields(worlds.template, values, len(rows))


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
    sims: Sequence[StartedSimulation]
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


def _run_warp(
    parts: Sequence[_WarpPart],
    device: str,
    columns: CostColumns | None,
    models: Sequence[mujoco.MjModel] | WorldFields,
) -> None:
    """Roll every part's candidates out on MuJoCo Warp in one batch, filling their rows.

    Only the rows the signals read are recorded, on the device, with ``qpos``,
    ``sensordata`` and the site kinematics (which lag one step, as after ``mj_step``), or,
    with ``columns``, only those columns, the joint term summed on the device into each
    part's ``square``; MuJoCo Warp checks every step for divergence. ``models``: the
    worlds' models, in the parts' order.
    """
    from zmpkit.sim.warp_batch import rollout_warp

    table = _control_table(parts, isinstance(models, WorldFields))
    sims = [s for part in parts for s in part.sims]
    group = np.repeat(np.arange(len(parts)), [len(part.sims) for part in parts])
    initial = _initial_states(sims)
    ft_samples = columns is None or any(any(part.rows.sensors) for part in parts)
    kept = [part.kept_steps(ft_samples) for part in parts]
    record_steps = np.unique(np.concatenate(kept))
    square = None if columns is None else _square_error(parts)
    result = rollout_warp(
        models,
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
        _read_part(part, result, worlds, steps_kept, nsite, initial[worlds, 0])


def _control_table(parts: Sequence[_WarpPart], shared: bool) -> NDArray[np.float64]:
    """Each part's controls, ``(nparts, nstep, nu)``: a shorter one holds its last row.

    ``shared``: the candidates share one model's actuator gears (no check needed).
    """
    controls = []
    for part in parts:
        mine = part.sims[0].controls_of(part.schedule.setpoints_rad)
        if not shared and any(
            not np.array_equal(s.controls_of(part.schedule.setpoints_rad), mine) for s in part.sims
        ):
            raise ParameterError(
                "the Warp backend needs the same actuator gears in every candidate"
            )
        controls.append(mine)
    longest = max(len(c) for c in controls)
    return np.stack([np.concatenate([c, np.repeat(c[-1:], longest - len(c), 0)]) for c in controls])


def _initial_states(sims: Sequence[StartedSimulation]) -> NDArray[np.float64]:
    """Each posed simulation's ``mjSTATE_FULLPHYSICS`` state, ``(nsims, nstate)``."""
    full = mujoco.mjtState.mjSTATE_FULLPHYSICS
    initial = np.empty((len(sims), mujoco.mj_stateSize(sims[0].model, full)))
    for i, sim in enumerate(sims):
        if isinstance(sim, PosedSimulation):
            initial[i] = sim.data.state
        else:
            mujoco.mj_getState(sim.model, sim.data, initial[i], full)
    return initial


def _square_error(parts: Sequence[_WarpPart]) -> QposSquareError:
    """The joint term each world sums on the device: its encoders against the recorded."""
    targets = [part.target_rows() for part in parts]
    return joint_square_error(
        [part.sims[0] for part in parts],
        [part.rows.experiment.signals.joint_names for part in parts],
        [steps for steps, _ in targets],
        [rows for _, rows in targets],
    )


def _read_part(
    part: _WarpPart,
    result: WarpRollout,
    worlds: slice,
    steps_kept: NDArray[np.int64],
    nsite: int,
    t0: NDArray[np.float64],
) -> None:
    """Fill ``part``'s rows (and its joint term) from its ``worlds`` of the batch."""
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
    measured = ft_readings(part.rows, part.sims, alive, out["sensordata"][:, ft_rows])
    warned = np.zeros((n, int(mujoco.mjtWarning.mjNWARNING)), dtype=bool)
    read_candidates(
        part.rows, alive, out, steps, ft_rows, measured, warned, t0, part.sims[0].dt, valid
    )
