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
the fields in which they differ become per-world ("batched") MuJoCo Warp model arrays.
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

This module does not import ``from __future__ import annotations``: Warp reads the
annotations of the kernels defined below at run time.
"""

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError, ParameterError
from zmpkit.sim.warp_cache import configure_kernel_cache
from zmpkit.sim.warp_columns import QposSquareError, check_square_error, record_columns
from zmpkit.sim.warp_kernels import step_kernels
from zmpkit.sim.warp_model import batched_fields, check_supported
from zmpkit.sim.warp_session import Plan, Session, clear_warp_cache, plan_for, session_for
from zmpkit.sim.world import DIVERGED_SPEED_RAD_S

__all__ = [
    "DEFAULT_STEPS_PER_LAUNCH",
    "RECORDABLE",
    "QposSquareError",
    "WarpRollout",
    "clear_warp_cache",
    "rollout_warp",
    "warp_runtime",
]

_INSTALL_HINT = "pip install 'zmpkit[gpu]'"  # the extra: mujoco-warp==4.0.0 (brings warp-lang)
_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)
DEFAULT_STEPS_PER_LAUNCH = 50
"""Physics steps per graph launch on CUDA (a loop of launches on the CPU). Not tuned: no
GPU has measured it; ``benchmarks/bench_warp_batch.py --steps-per-launch`` compares."""
RECORDABLE = ("state", "qpos", "qvel", "act", "sensordata", "site_xpos", "site_xmat")
"""What :func:`rollout_warp` can record per row: the ``mjSTATE_FULLPHYSICS`` state, or the
named ``mjData`` arrays (``site_xpos`` as ``(nsite * 3)``, ``site_xmat`` as ``(nsite * 9)``)."""
_NEVER = np.iinfo(np.int32).max
"""The first failing step of a world that never failed."""


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


def _import_warp() -> tuple[Any, Any]:
    try:
        import mujoco_warp
        import warp
    except ImportError as exc:
        raise ModuleNotFoundError(
            f"rollout_warp needs MuJoCo Warp, which is not installed ({exc}); "
            f"install it with: {_INSTALL_HINT}"
        ) from exc
    configure_kernel_cache(warp)  # before warp.init(): zmpkit's persistent kernel cache
    _quiet_warp(warp)
    return warp, mujoco_warp


def _quiet_warp(wp: Any) -> None:
    """Warp's log level raised from its default (info) to warnings.

    At info Warp prints its start-up banner and a line per kernel module it loads (about 60
    per fit), which would bury a command's own output; warnings (a missing CUDA driver, a
    kernel that failed to compile) still show. A level other than the default is kept.
    """
    if wp.config.log_level == wp.LOG_INFO:
        wp.config.log_level = wp.LOG_WARNING


def _check_inputs(
    model: mujoco.MjModel,
    nbatch: int,
    initial_state: NDArray[Any],
    control: NDArray[Any],
    control_group: NDArray[Any] | Sequence[int] | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int32]]:
    """The initial states, the controls as ``(ngroup, nstep, nu)`` and each item's group."""
    nstate = mujoco.mj_stateSize(model, _FULL)
    state = np.asarray(initial_state, dtype=np.float64)
    ctrl = np.asarray(control, dtype=np.float64)
    if ctrl.ndim == 3:
        groups = np.arange(nbatch) if control_group is None else np.asarray(control_group)
        if (
            groups.shape != (nbatch,)
            or not np.issubdtype(groups.dtype, np.integer)
            or groups.min() < 0
            or groups.max() >= len(ctrl)
        ):
            raise ParameterError(
                f"control_group must give each of the {nbatch} items a control sequence in "
                f"[0, {len(ctrl)}), got {control_group!r}"
            )
    elif control_group is not None:
        raise ParameterError("control_group needs control of shape (ngroup, nstep, nu)")
    else:
        groups, ctrl = np.zeros(nbatch, dtype=np.int64), ctrl[None]
    if state.shape not in ((nstate,), (nbatch, nstate)) or not np.all(np.isfinite(state)):
        raise ParameterError(
            f"initial_state must be finite mjSTATE_FULLPHYSICS states of shape ({nstate},) or "
            f"({nbatch}, {nstate}), got shape {state.shape}"
        )
    if ctrl.ndim != 3 or ctrl.shape[2] != model.nu or ctrl.shape[1] == 0:
        raise ParameterError(
            f"control must have shape (nstep, nu={model.nu}) or (ngroup, nstep, nu) with "
            f"nstep >= 1, got {np.shape(control)}"
        )
    if not np.all(np.isfinite(ctrl)):
        raise ParameterError("control must be finite")
    return state, ctrl, groups.astype(np.int32)


def _record_steps(
    nstep: int, record_every: int, record_steps: Sequence[int] | NDArray[Any] | None
) -> NDArray[np.int64]:
    """The steps after which rows are taken, sorted (1 is after the first step)."""
    if record_steps is None:
        if not isinstance(record_every, int | np.integer) or not 1 <= record_every <= nstep:
            raise ParameterError(
                f"record_every must be an integer in [1, nstep={nstep}], got {record_every!r}"
            )
        return (np.arange(nstep // int(record_every)) + 1) * int(record_every)
    if record_every != 1:
        raise ParameterError("give record_every or record_steps, not both")
    steps = np.asarray(record_steps)
    if (
        steps.ndim != 1
        or len(steps) == 0
        or not np.issubdtype(steps.dtype, np.integer)
        or steps.min() < 1
        or steps.max() > nstep
    ):
        raise ParameterError(
            f"record_steps must be a non-empty 1-D set of integer steps in [1, nstep={nstep}]"
        )
    return np.unique(steps).astype(np.int64)


def _check_records(record: Sequence[str], steps_per_launch: int) -> tuple[str, ...]:
    names = tuple(record)
    if not names or len(set(names)) != len(names) or not set(names) <= set(RECORDABLE):
        raise ParameterError(f"record must name distinct arrays among {RECORDABLE}, got {names!r}")
    if isinstance(steps_per_launch, bool) or not isinstance(steps_per_launch, int | np.integer):
        raise ParameterError(f"steps_per_launch must be an integer >= 1, got {steps_per_launch!r}")
    if steps_per_launch < 1:
        raise ParameterError(f"steps_per_launch must be an integer >= 1, got {steps_per_launch!r}")
    return names


def warp_runtime(device: str | None = None) -> tuple[Any, str]:
    """Warp, started with zmpkit's kernel cache, and the name of ``device`` on it.

    Args:
        device: Warp device (``"cuda:0"``, ``"cpu"``); ``None`` is Warp's default.

    Returns:
        The ``warp`` module and the device's name, e.g. ``"cuda:0"`` or ``"cpu"``.

    Raises:
        ModuleNotFoundError: MuJoCo Warp is not installed (``pip install 'zmpkit[gpu]'``).
        ParameterError: an unknown device.
    """
    wp, _ = _import_warp()
    return wp, str(_device(wp, device))


def _device(wp: Any, device: str | None) -> Any:
    try:
        return wp.get_device(device)
    except (RuntimeError, ValueError) as exc:
        valid = [str(d) for d in wp.get_devices()]
        raise ParameterError(f"unknown Warp device {device!r}; available: {valid}") from exc


def _one_step(wp: Any, mjw: Any, session: Session, plan: Plan) -> Callable[[], None]:
    """One physics step of every world: controls, step, divergence check, records."""
    k = step_kernels()
    m, d = session.m, session.d
    nworld, nu = d.nworld, session.template.nu
    sources = {
        "qpos": d.qpos,
        "qvel": d.qvel,
        "act": d.act,
        "sensordata": d.sensordata,
        "state": plan.scratch,
    }
    launches = []  # (kernel, source, columns, output, columns launched)
    for name, out in plan.outputs.items():
        cols = plan.columns[name]
        if name == "site_xpos":
            launches.append((k["record_vec3"], d.site_xpos, cols, out, cols.shape[0]))
        elif name == "site_xmat":
            launches.append((k["record_mat33"], d.site_xmat, cols, out, cols.shape[0]))
        else:
            launches.append((k["record"], sources[name], cols, out, cols.shape[0]))
    limit, never = wp.float64(DIVERGED_SPEED_RAD_S), wp.int32(_NEVER)
    sq = plan.square

    def step() -> None:
        if nu:
            wp.launch(
                k["set_ctrl"],
                dim=(nworld, nu),
                inputs=[plan.control, plan.group, plan.counter],
                outputs=[d.ctrl],
            )
        mjw.step(m, d)
        wp.launch(
            k["check"],
            dim=nworld,
            inputs=[d.qpos, d.qvel, d.act, plan.counter, limit, never],
            outputs=[plan.first_bad],
        )
        if plan.scratch is not None:
            mjw.get_state(m, d, plan.scratch, _FULL, plan.every_world)
        for kernel, source, cols, out, ncols in launches:
            if not ncols:
                continue
            wp.launch(
                kernel,
                dim=(nworld, ncols),
                inputs=[source, cols, plan.counter, plan.row_of_step],
                outputs=[out],
            )
        if sq is not None:
            wp.launch(
                k["square_error"],
                dim=nworld,
                inputs=[
                    d.qpos,
                    sq.columns,
                    sq.quantum,
                    plan.group,
                    plan.counter,
                    sq.row_of_step,
                    sq.target,
                ],
                outputs=[sq.total],
            )
        wp.launch(k["advance"], dim=1, inputs=[plan.counter])

    return step


def _run_steps(wp: Any, step: Callable[[], None], plan: Plan, nstep: int, per_launch: int) -> None:
    """``nstep`` steps: on CUDA as replays of captured graphs of ``per_launch`` steps."""
    if not wp.get_device().is_cuda:
        for _ in range(nstep):
            step()
        return
    done = 0
    if not plan.graphs:  # the first step runs eagerly: it compiles and loads the modules
        step()
        done = 1
    while done < nstep:
        count = min(per_launch, nstep - done)
        if count not in plan.graphs:
            with wp.ScopedCapture() as capture:
                for _ in range(count):
                    step()
            plan.graphs[count] = capture.graph
        wp.capture_launch(plan.graphs[count])
        done += count


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
    models: Sequence[mujoco.MjModel],
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
        models: one model per batch item, all compiled from the same MJCF; the fields in
            which they differ are given to MuJoCo Warp per world.
        initial_state: ``mjSTATE_FULLPHYSICS`` state, ``(nstate,)`` shared by all items or
            ``(nbatch, nstate)`` one each.
        control: ``(nstep, nu)`` ``ctrl`` for every step, shared by all items (actuator
            units, e.g. motor-side position setpoints [rad] for zmpkit's dcmotors), or
            ``(ngroup, nstep, nu)``: several sequences (experiments), one per item or
            chosen by ``control_group``; pad a shorter one (e.g. by holding its last row).
        record_every: keep a row after every ``record_every``-th step; ``nstep %
            record_every`` trailing steps are not simulated.
        device: Warp device (``"cuda:0"``, ``"cpu"``); ``None`` is Warp's default.
        record_steps: instead of ``record_every``, the steps after which to keep a row
            (1 is after the first step; sorted, duplicates dropped); steps after the last
            are not simulated.
        record: what each row keeps (:data:`RECORDABLE`); the rest never leaves the device.
        steps_per_launch: steps per captured graph on CUDA (a loop of launches on the CPU;
            the result does not depend on it).
        control_group: with 3-D ``control``, ``(nbatch,)`` the sequence each item runs
            (``None``: item ``i`` runs sequence ``i``).
        nconmax: contacts per world to allocate (MuJoCo Warp's default if ``None``).
        njmax: constraint rows per world to allocate (MuJoCo Warp's default if ``None``).
        columns: per recorded name, the columns each row keeps, in this order (entries of
            ``qpos``, ``qvel``, ``act``, ``sensordata``; sites of ``site_xpos`` and
            ``site_xmat``, 3 and 9 values each); a name left out keeps every column
            (``state`` always does).
        square_error: a sum of squared qpos errors to accumulate per world on the device,
            every step (:class:`QposSquareError`); returned as
            :attr:`WarpRollout.square_error`.

    Returns:
        The recorded rows: row ``k`` is after step ``steps[k]``.

    Raises:
        ModuleNotFoundError: MuJoCo Warp is not installed (``pip install 'zmpkit[gpu]'``).
        ParameterError: bad shapes, an unknown device, models that differ in a field Warp
            cannot batch, or a model feature MuJoCo Warp does not support.
        ModelError: a world that did not diverge overflowed the contact/constraint buffers.
    """
    wp, mjw = _import_warp()
    if len(models) == 0 or not all(isinstance(m, mujoco.MjModel) for m in models):
        raise ParameterError("models must be a non-empty sequence of mujoco.MjModel")
    template = models[0]
    state0, ctrl, groups = _check_inputs(
        template, len(models), initial_state, control, control_group
    )
    steps = _record_steps(ctrl.shape[1], record_every, record_steps)
    records = _check_records(record, steps_per_launch)
    kept = record_columns(template, records, columns)
    state0 = np.broadcast_to(state0, (len(models), state0.shape[-1]))
    check_supported(mjw, template)
    fields = batched_fields(mjw, models)
    nstep = int(steps[-1])
    row_of_step = np.full(nstep, -1, dtype=np.int32)
    row_of_step[steps - 1] = np.arange(len(steps), dtype=np.int32)
    check_square_error(square_error, template, len(ctrl), nstep)
    square_shape = None
    if square_error is not None:
        square_targets = square_error.padded_targets()
        square_shape = (square_targets.shape[1], square_targets.shape[2])
    with wp.ScopedDevice(_device(wp, device)):
        name = str(wp.get_device())
        session = session_for(wp, mjw, models, fields, name, nconmax, njmax)
        plan = plan_for(wp, session, len(ctrl), nstep, len(steps), kept, square_shape)
        m, d = session.m, session.d
        mjw.reset_data(m, d)
        mjw.set_state(m, d, wp.array(np.ascontiguousarray(state0), dtype=float), _FULL)
        if template.nu:
            plan.control.assign(ctrl[:, :nstep])
        plan.group.assign(groups)
        plan.row_of_step.assign(row_of_step)
        plan.counter.zero_()
        plan.first_bad.fill_(_NEVER)
        if square_error is not None and plan.square is not None:
            sq = plan.square
            sq.columns.assign(np.asarray(square_error.columns, dtype=np.int32))
            sq.quantum.assign(np.asarray(square_error.quantum, dtype=np.float64))
            sq.row_of_step.assign(square_error.row_of_step(nstep))
            sq.target.assign(square_targets)
            sq.total.zero_()
        _run_steps(wp, _one_step(wp, mjw, session, plan), plan, nstep, int(steps_per_launch))
        wp.synchronize_device()
        out = {k: v.numpy() for k, v in plan.outputs.items()}
        first_bad = plan.first_bad.numpy()
        overflow = d.overflow.numpy()
        total = None if plan.square is None else plan.square.total.numpy()
    recorded = {
        k: np.ascontiguousarray(v.transpose(1, 0, 2), dtype=np.float64) for k, v in out.items()
    }
    timestep = np.array([mm.opt.timestep for mm in models])
    time = state0[:, :1] + timestep[:, None] * steps[None, :]
    if "state" in recorded:
        recorded["state"][:, :, 0] = time
    valid = _valid_rows(first_bad, steps)
    capped = _overflow_check(mjw, overflow, valid == len(steps))
    return WarpRollout(recorded, steps, time, valid, capped, fields, name, total)
