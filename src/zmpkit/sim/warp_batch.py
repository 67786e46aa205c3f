"""Batched open-loop rollouts on MuJoCo Warp: one world per model, all stepped together.

:func:`rollout_warp` has the contract of :func:`mujoco.rollout.rollout` for open-loop
controls shared by every batch item, with only the rows and the arrays asked for kept:
row ``k`` of the outputs is taken after step ``steps[k]`` (every ``record_every``-th step,
or the explicit ``record_steps``), and holds the arrays named in ``record`` (the full
``mjSTATE_FULLPHYSICS`` state, ``qpos``, ``qvel``, ``act``, ``sensordata``, and the site
kinematics ``site_xpos``/``site_xmat``, which lag one step as after ``mj_step``), each
limited to the ``columns`` asked for. The rows are written on the device inside the step
loop; nothing else leaves it. A sum of squared qpos errors against targets at given steps
(:class:`QposSquareError`, a fit's joint term) can be accumulated per world on the device
instead, so that one number per world comes back.
The models are one MJCF with different parameters (a CMA-ES generation's candidates);
the fields in which they differ become per-world ("batched") MuJoCo Warp model arrays; or
one compiled model comes with its per-world fields already written
(:class:`~zmpkit.sim.world_fields.WorldFields`, no model per candidate).
Runs on a CUDA device (the point) or on Warp's CPU device (tests); ``pip install
'zmpkit[gpu]'``.

Launches: each physics step is a few kernel launches (controls, ``mujoco_warp.step``, the
divergence check, the records: :mod:`~zmpkit.sim.warp_kernels`). On CUDA
``steps_per_launch`` steps are captured as one graph and replayed; on the CPU the same
steps run as a loop of launches. The Warp model,
data, buffers and graphs are kept between calls of the same shapes
(:mod:`~zmpkit.sim.warp_session`, keyed by the model layout, the per-world fields, the
number of worlds and the buffers' sizes): a
fit's next generation only copies its candidates' per-world fields, initial states and
controls in, resets the data and replays. :func:`clear_warp_cache` releases them.

Differences from CPU MuJoCo, measured in ``tests/sim/test_warp_batch.py`` and the report of
issue 7:

- MuJoCo Warp computes in float32 (state in, state out, solver ``tolerance >= 1e-6``).
  The time column is recomputed here in float64 as ``t0 + n * timestep``.
- A world that diverges is not reset (CPU ``mj_step`` resets to ``qpos0`` on a bad
  ``qacc``): its state runs away or turns non-finite (NaN stays NaN). Every step, on the
  device, a world's ``qpos``, ``qvel`` and ``act`` are checked (finite, every ``|qvel|``
  within :data:`~zmpkit.sim.world.DIVERGED_SPEED_RAD_S`, the limit of
  :class:`~zmpkit.sim.world.Simulation`); :attr:`WarpRollout.valid_rows` counts the rows
  taken before its first failing step, recorded or not. The other worlds are unaffected.
- Unsupported features (e.g. the ``pid`` servo of zmpkit's ideal joint: ``mjDYN_PID``)
  raise :class:`~zmpkit.errors.ParameterError`; the CPU backend handles every model.

The inputs are checked in :mod:`~zmpkit.sim.warp_inputs`, Warp started in
:mod:`~zmpkit.sim.warp_runtime`, the step loop is :mod:`~zmpkit.sim.warp_step`.
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError, ParameterError
from zmpkit.sim.warp_columns import QposSquareError, check_square_error, record_columns
from zmpkit.sim.warp_inputs import RECORDABLE, check_inputs, check_records, record_steps
from zmpkit.sim.warp_model import batched_fields, check_supported, world_fields_for_warp
from zmpkit.sim.warp_runtime import import_warp, warp_device, warp_runtime
from zmpkit.sim.warp_session import Plan, Session, clear_warp_cache, plan_for, session_for
from zmpkit.sim.warp_step import NEVER_FAILED, one_step, run_steps
from zmpkit.sim.world_fields import WorldFields

__all__ = [
    "DEFAULT_STEPS_PER_LAUNCH",
    "RECORDABLE",
    "QposSquareError",
    "WarpRollout",
    "clear_warp_cache",
    "rollout_warp",
    "warp_runtime",
]

_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)
DEFAULT_STEPS_PER_LAUNCH = 50
"""Physics steps per graph launch on CUDA (a loop of launches on the CPU). Not tuned: no
GPU has measured it; ``benchmarks/bench_warp_batch.py --steps-per-launch`` compares."""


@dataclass(frozen=True)
class WarpRollout:
    """Recorded rollouts of a batch, as float64 numpy arrays.

    Attributes:
        records: per recorded name (:data:`RECORDABLE`), ``(nbatch, nrec, n)``: the
            ``mjSTATE_FULLPHYSICS`` state (time [s], qpos, qvel, act, ...), ``qpos``,
            ``qvel``, ``act``, noiseless ``sensordata``, ``site_xpos`` [m] (``nsite * 3``)
            and ``site_xmat`` (``nsite * 9``, row-major) in MuJoCo units and frames.
        steps: ``(nrec,)`` the step after which each row was taken (1 is after the first).
        time: ``(nbatch, nrec)`` the time of each row [s] (``t0 + step * timestep``).
        valid_rows: ``(nbatch,)`` number of leading rows taken before the world's first
            step with a non-finite ``qpos``/``qvel``/``act`` or a ``|qvel|`` above
            ``DIVERGED_SPEED_RAD_S``; rows after are not to be used.
        solver_capped: ``(nbatch,)`` the constraint solver or its line search hit the
            iteration limit at least once (as CPU MuJoCo's unconverged solver: tolerated).
        batched_fields: model fields given per world (``opt.`` prefix for options).
        device: the Warp device that ran it, e.g. ``"cuda:0"`` or ``"cpu"``.
        square_error: ``(nbatch,)`` the sum of the ``square_error`` asked for, per world
            (float64, accumulated on the device; NaN or garbage past a divergence), or None.
    """

    records: Mapping[str, NDArray[np.float64]]
    steps: NDArray[np.int64]
    time: NDArray[np.float64]
    valid_rows: NDArray[np.int64]
    solver_capped: NDArray[np.bool_]
    batched_fields: tuple[str, ...]
    device: str
    square_error: NDArray[np.float64] | None = None

    @property
    def state(self) -> NDArray[np.float64]:
        """``(nbatch, nrec, nstate)`` the recorded ``mjSTATE_FULLPHYSICS`` states."""
        return self._record("state")

    @property
    def sensordata(self) -> NDArray[np.float64]:
        """``(nbatch, nrec, nsensordata)`` the recorded noiseless sensor readings."""
        return self._record("sensordata")

    @property
    def diverged(self) -> NDArray[np.bool_]:
        """``(nbatch,)`` worlds that diverged (non-finite state or runaway speed)."""
        return self.valid_rows < len(self.steps)

    def _record(self, name: str) -> NDArray[np.float64]:
        if name not in self.records:
            raise KeyError(f"{name!r} was not recorded; recorded: {sorted(self.records)}")
        return self.records[name]


def _valid_rows(first_bad: NDArray[Any], steps: NDArray[np.int64]) -> NDArray[np.int64]:
    """Per world, the rows taken before its first failing step."""
    return np.searchsorted(steps, first_bad, side="left").astype(np.int64)


def _overflow_check(mjw: Any, overflow: NDArray[Any], healthy: NDArray[np.bool_]) -> NDArray[Any]:
    """Raise on a buffer overflow in a healthy world; the solver-cap flag per world."""
    kinds = mjw.OverflowType
    capped = kinds.ITERATIONS | kinds.LS_ITERATIONS
    hard = np.where(healthy, overflow & ~int(capped), 0)
    if np.any(hard):
        world = int(np.flatnonzero(hard)[0])
        raise ModelError(
            f"MuJoCo Warp ran out of buffer in world {world} ({kinds(int(hard[world])).name}): "
            "contacts or constraints were dropped; pass larger nconmax / njmax"
        )
    return (overflow & int(capped)) != 0


def rollout_warp(
    models: Sequence[mujoco.MjModel] | WorldFields,
    initial_state: NDArray[Any],
    control: NDArray[Any],
    record_every: int = 1,
    device: str | None = None,
    *,
    record_steps: Sequence[int] | NDArray[Any] | None = None,
    record: Sequence[str] = ("state", "sensordata"),
    steps_per_launch: int = DEFAULT_STEPS_PER_LAUNCH,
    control_group: NDArray[Any] | Sequence[int] | None = None,
    nconmax: int | None = None,
    njmax: int | None = None,
    columns: Mapping[str, Sequence[int]] | None = None,
    square_error: QposSquareError | None = None,
) -> WarpRollout:
    """Roll out every model from its state under open-loop control sequences, batched.

    Args:
        models: one model per item, compiled from one MJCF (fields that differ: per world);
            or one compiled model with its per-world fields already written
            (:class:`~zmpkit.sim.world_fields.WorldFields`: no comparison of models).
        initial_state: ``mjSTATE_FULLPHYSICS`` state, ``(nstate,)`` shared or ``(nbatch,
            nstate)`` one each.
        control: ``ctrl`` per step (actuator units, e.g. [rad] at a dcmotor's rotor):
            ``(nstep, nu)`` shared, or ``(ngroup, nstep, nu)`` sequences (experiments), a
            shorter one padded (e.g. holding its last row).
        record_every: a row after every ``record_every``-th step (the ``nstep %
            record_every`` trailing steps are not simulated).
        device: Warp device (``"cuda:0"``, ``"cpu"``); ``None`` is Warp's default.
        record_steps: instead, the steps after which to keep a row (1 is after the first;
            sorted, duplicates dropped; later steps are not simulated).
        record: what each row keeps (:data:`RECORDABLE`); the rest never leaves the device.
        steps_per_launch: steps per captured CUDA graph (the result does not depend on it).
        control_group: with 3-D ``control``, ``(nbatch,)`` the sequence each item runs
            (``None``: item ``i`` runs sequence ``i``).
        nconmax: contacts per world to allocate (``None``: MuJoCo Warp's default).
        njmax: constraint rows per world to allocate (``None``: MuJoCo Warp's default).
        columns: per recorded name, the columns each row keeps, in order (entries; sites of
            ``site_xpos``/``site_xmat``, 3 and 9 values each); left out: all (``state``).
        square_error: squared qpos errors to sum per world on the device, every step
            (:class:`QposSquareError`), returned as :attr:`WarpRollout.square_error`.

    Returns:
        The recorded rows: row ``k`` is after step ``steps[k]``.

    Raises:
        ModuleNotFoundError: MuJoCo Warp is not installed (``pip install 'zmpkit[gpu]'``).
        ParameterError: bad shapes, an unknown device, models that differ in a field Warp
            cannot batch, or a model feature MuJoCo Warp does not support.
        ModelError: a world that did not diverge overflowed the contact/constraint buffers.
    """
    wp, mjw = import_warp()
    inputs = _checked_inputs(
        mjw, models, initial_state, control, control_group, record_every, record_steps,
        record, steps_per_launch, columns, square_error,
    )  # fmt: skip
    with wp.ScopedDevice(warp_device(wp, device)):
        run = _run(wp, mjw, inputs, (nconmax, njmax), int(steps_per_launch), square_error)
    return _rollout(mjw, inputs, run)


@dataclass(frozen=True)
class _Run:
    """What a rollout's device run hands back (float32 numpy arrays, as on the device).

    Attributes:
        out: per recorded name, ``(nrec, nbatch, n)`` the rows.
        first_bad: ``(nbatch,)`` each world's first failing step.
        overflow: ``(nbatch,)`` each world's MuJoCo Warp overflow flags.
        square_error: ``(nbatch,)`` the summed squared qpos errors, or None.
        device: the Warp device's name.
    """

    out: dict[str, NDArray[Any]]
    first_bad: NDArray[Any]
    overflow: NDArray[Any]
    square_error: NDArray[Any] | None
    device: str


def _run(
    wp: Any,
    mjw: Any,
    inputs: "_Inputs",
    buffers: tuple[int | None, int | None],
    steps_per_launch: int,
    square_error: QposSquareError | None,
) -> _Run:
    """Run the batch on the current device; ``buffers``: (nconmax, njmax) per world."""
    name = str(wp.get_device())
    session = session_for(wp, mjw, inputs.worlds, name, *buffers)
    nstep, nrec = inputs.nstep, len(inputs.steps)
    plan = plan_for(
        wp, session, len(inputs.control), nstep, nrec, inputs.columns, inputs.square_shape
    )
    _load(wp, mjw, session, plan, inputs, square_error)
    run_steps(wp, one_step(wp, mjw, session, plan), plan, nstep, steps_per_launch)
    wp.synchronize_device()
    out = {k: v.numpy() for k, v in plan.outputs.items()}
    first_bad = plan.first_bad.numpy()
    overflow = session.d.overflow.numpy()
    total = None if plan.square is None else plan.square.total.numpy()
    return _Run(out, first_bad, overflow, total, name)


def _rollout(mjw: Any, inputs: "_Inputs", run: _Run) -> WarpRollout:
    """The rollout's records as float64, with their times, valid rows and solver flags."""
    steps = inputs.steps
    recorded = {
        k: np.ascontiguousarray(v.transpose(1, 0, 2), dtype=np.float64) for k, v in run.out.items()
    }
    worlds = inputs.worlds
    timestep = np.broadcast_to(
        worlds.values.get("opt.timestep", worlds.template.opt.timestep), (len(worlds),)
    )
    time = inputs.state0[:, :1] + timestep[:, None] * steps[None, :]
    if "state" in recorded:
        recorded["state"][:, :, 0] = time
    valid = _valid_rows(run.first_bad, steps)
    capped = _overflow_check(mjw, run.overflow, valid == len(steps))
    return WarpRollout(
        recorded, steps, time, valid, capped, inputs.fields, run.device, run.square_error
    )


@dataclass(frozen=True)
class _Inputs:
    """A rollout's checked inputs, laid out for the device.

    Attributes:
        state0: ``(nbatch, nstate)`` each item's initial ``mjSTATE_FULLPHYSICS`` state.
        control: ``(ngroup, nstep, nu)`` the control sequences.
        groups: ``(nbatch,)`` the sequence each item runs.
        steps: ``(nrec,)`` the steps after which rows are taken.
        columns: per recorded name, the columns each row keeps.
        worlds: the template and the model fields given per world.
        row_of_step: ``(nstep,)`` the row taken after each step, -1 for none.
        square_targets: the padded targets of the squared joint errors, or None.
    """

    state0: NDArray[np.float64]
    control: NDArray[np.float64]
    groups: NDArray[np.int32]
    steps: NDArray[np.int64]
    columns: dict[str, tuple[int, ...]]
    worlds: WorldFields
    row_of_step: NDArray[np.int32]
    square_targets: NDArray[np.float64] | None

    @property
    def fields(self) -> tuple[str, ...]:
        """The model fields given per world."""
        return self.worlds.names

    @property
    def nstep(self) -> int:
        """Steps simulated: up to the last recorded row."""
        return int(self.steps[-1])

    @property
    def square_shape(self) -> tuple[int, int] | None:
        """The (rows, columns) of each control group's squared-error targets, or None."""
        if self.square_targets is None:
            return None
        return (self.square_targets.shape[1], self.square_targets.shape[2])


def _checked_inputs(
    mjw: Any,
    models: Sequence[mujoco.MjModel] | WorldFields,
    initial_state: NDArray[Any],
    control: NDArray[Any],
    control_group: NDArray[Any] | Sequence[int] | None,
    record_every: int,
    steps_asked: Sequence[int] | NDArray[Any] | None,
    record: Sequence[str],
    steps_per_launch: int,
    columns: Mapping[str, Sequence[int]] | None,
    square_error: QposSquareError | None,
) -> _Inputs:
    """:func:`rollout_warp`'s arguments checked (its Raises) and laid out for the device."""
    worlds = _worlds(mjw, models)
    template = worlds.template
    state0, ctrl, groups = check_inputs(
        template, len(models), initial_state, control, control_group
    )
    steps = record_steps(ctrl.shape[1], record_every, steps_asked)
    records = check_records(record, steps_per_launch)
    kept = record_columns(template, records, columns)
    state0 = np.broadcast_to(state0, (len(models), state0.shape[-1]))
    check_supported(mjw, template)
    nstep = int(steps[-1])
    row_of_step = np.full(nstep, -1, dtype=np.int32)
    row_of_step[steps - 1] = np.arange(len(steps), dtype=np.int32)
    check_square_error(square_error, template, len(ctrl), nstep)
    targets = None if square_error is None else square_error.padded_targets()
    return _Inputs(state0, ctrl, groups, steps, kept, worlds, row_of_step, targets)


def _worlds(mjw: Any, models: Sequence[mujoco.MjModel] | WorldFields) -> WorldFields:
    """The template and per-world fields of ``models`` (checked as :func:`rollout_warp` says)."""
    if isinstance(models, WorldFields):
        return world_fields_for_warp(mjw, models)
    if len(models) == 0 or not all(isinstance(m, mujoco.MjModel) for m in models):
        raise ParameterError("models must be a non-empty sequence of mujoco.MjModel")
    return WorldFields.of_models(models, batched_fields(mjw, models))


def _load(
    wp: Any,
    mjw: Any,
    session: Session,
    plan: Plan,
    inputs: _Inputs,
    square_error: QposSquareError | None,
) -> None:
    """Reset the session's data and copy the rollout's states, controls and targets in."""
    m, d = session.m, session.d
    mjw.reset_data(m, d)
    mjw.set_state(m, d, wp.array(np.ascontiguousarray(inputs.state0), dtype=float), _FULL)
    if inputs.control.shape[2]:  # the model's nu
        plan.control.assign(inputs.control[:, : inputs.nstep])
    plan.group.assign(inputs.groups)
    plan.row_of_step.assign(inputs.row_of_step)
    plan.counter.zero_()
    plan.first_bad.fill_(NEVER_FAILED)
    if square_error is not None and plan.square is not None:
        sq = plan.square
        sq.columns.assign(np.asarray(square_error.columns, dtype=np.int32))
        sq.quantum.assign(np.asarray(square_error.quantum, dtype=np.float64))
        sq.row_of_step.assign(square_error.row_of_step(inputs.nstep))
        sq.target.assign(inputs.square_targets)
        sq.total.zero_()
