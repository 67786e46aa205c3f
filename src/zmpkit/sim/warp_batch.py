"""Batched open-loop rollouts on MuJoCo Warp: one world per model, all stepped together.

:func:`rollout_warp` has the contract of :func:`mujoco.rollout.rollout` for open-loop
controls shared by every batch item, subsampled: row ``k`` of the outputs is the state
(``mjSTATE_FULLPHYSICS``) and ``sensordata`` after step ``(k + 1) * record_every``.
The models are one MJCF with different parameters (a CMA-ES generation's candidates);
the fields in which they differ become per-world ("batched") MuJoCo Warp model arrays.
Runs on a CUDA device (the point) or on Warp's CPU device (tests); ``pip install
'zmpkit[gpu]'``. On CUDA each step and each record is replayed as a captured graph.

Differences from CPU MuJoCo, measured in ``tests/sim/test_warp_batch.py`` and the report of
issue 7:

- MuJoCo Warp computes in float32 (state in, state out, solver ``tolerance >= 1e-6``).
  The time column is recomputed here in float64 as ``t0 + n * timestep``.
- A world that diverges is not reset (CPU ``mj_step`` resets to ``qpos0`` on a bad
  ``qacc``): its state runs away or turns non-finite (NaN stays NaN), and
  :attr:`WarpRollout.valid_rows` counts its leading rows that are finite with every
  ``|qvel|`` within :data:`~zmpkit.sim.world.DIVERGED_SPEED_RAD_S` (the limit of
  :class:`~zmpkit.sim.world.Simulation`). The other worlds are unaffected.
- Unsupported features (e.g. the ``pid`` servo of zmpkit's ideal joint: ``mjDYN_PID``)
  raise :class:`~zmpkit.errors.ParameterError`; the CPU backend handles every model.

This module does not import ``from __future__ import annotations``: Warp reads the
annotations of the kernels defined below at run time.
"""

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError, ParameterError
from zmpkit.sim.warp_cache import configure_kernel_cache
from zmpkit.sim.warp_model import batched_fields, check_supported, put_models
from zmpkit.sim.world import DIVERGED_SPEED_RAD_S

__all__ = ["WarpRollout", "rollout_warp", "warp_runtime"]

_INSTALL_HINT = "pip install 'zmpkit[gpu]'"  # the extra: mujoco-warp==4.0.0 (brings warp-lang)
_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)


@dataclass(frozen=True)
class WarpRollout:
    """Recorded rollouts of a batch, as float64 numpy arrays.

    Attributes:
        state: ``(nbatch, nrec, nstate)`` ``mjSTATE_FULLPHYSICS`` state after each recorded
            step (time [s], qpos, qvel, act, ...; MuJoCo units and frames).
        sensordata: ``(nbatch, nrec, nsensordata)`` noiseless MuJoCo sensor readings.
        valid_rows: ``(nbatch,)`` number of leading rows whose state is finite with
            every ``|qvel|`` <= ``DIVERGED_SPEED_RAD_S``; rows after are not to be used.
        solver_capped: ``(nbatch,)`` the constraint solver or its line search hit the
            iteration limit at least once (as CPU MuJoCo's unconverged solver: tolerated).
        batched_fields: model fields given per world (``opt.`` prefix for options).
        device: the Warp device that ran it, e.g. ``"cuda:0"`` or ``"cpu"``.
    """

    state: NDArray[np.float64]
    sensordata: NDArray[np.float64]
    valid_rows: NDArray[np.int64]
    solver_capped: NDArray[np.bool_]
    batched_fields: tuple[str, ...]
    device: str

    @property
    def diverged(self) -> NDArray[np.bool_]:
        """``(nbatch,)`` worlds that diverged (non-finite state or runaway speed)."""
        return self.valid_rows < self.state.shape[1]


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
    return warp, mujoco_warp


def _check_inputs(
    model: mujoco.MjModel,
    nbatch: int,
    initial_state: NDArray[Any],
    control: NDArray[Any],
    record_every: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    nstate = mujoco.mj_stateSize(model, _FULL)
    state = np.asarray(initial_state, dtype=np.float64)
    ctrl = np.asarray(control, dtype=np.float64)
    if state.shape not in ((nstate,), (nbatch, nstate)) or not np.all(np.isfinite(state)):
        raise ParameterError(
            f"initial_state must be finite mjSTATE_FULLPHYSICS states of shape ({nstate},) or "
            f"({nbatch}, {nstate}), got shape {state.shape}"
        )
    if ctrl.ndim != 2 or ctrl.shape[1] != model.nu or len(ctrl) == 0:
        raise ParameterError(
            f"control must have shape (nstep, nu={model.nu}) with nstep >= 1, got {ctrl.shape}"
        )
    if not np.all(np.isfinite(ctrl)):
        raise ParameterError("control must be finite")
    if not isinstance(record_every, int | np.integer) or not 1 <= record_every <= len(ctrl):
        raise ParameterError(
            f"record_every must be an integer in [1, nstep={len(ctrl)}], got {record_every!r}"
        )
    return state, ctrl


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


@functools.cache
def _kernels() -> tuple[Any, Any, Any]:
    """(set_ctrl, record, advance) Warp kernels, built once per process."""
    import warp as wp

    # Warp's kernel DSL reads these annotations at run time: its array types are calls, which
    # no static checker accepts as types, hence the ignores on each kernel parameter.
    @wp.kernel(enable_backward=False)
    def set_ctrl(
        control: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        counter: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        ctrl: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
    ):
        world, j = wp.tid()
        ctrl[world, j] = control[counter[0], j]

    @wp.kernel(enable_backward=False)
    def record(
        state: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        sensordata: wp.array2d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        counter: wp.array(dtype=wp.int32),  # type: ignore[valid-type]  # Warp's kernel DSL
        state_out: wp.array3d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
        sensordata_out: wp.array3d(dtype=float),  # type: ignore[valid-type]  # Warp's kernel DSL
    ):
        world = wp.tid()
        row = counter[0]
        for i in range(state.shape[1]):
            state_out[row, world, i] = state[world, i]
        for i in range(sensordata.shape[1]):
            sensordata_out[row, world, i] = sensordata[world, i]

    @wp.kernel(enable_backward=False)
    def advance(counter: wp.array(dtype=wp.int32)):  # type: ignore[valid-type]  # Warp's kernel DSL
        counter[0] = counter[0] + 1

    return set_ctrl, record, advance


def _graphed(wp: Any, fn: Callable[[], None]) -> Callable[[], None]:
    """``fn`` on the CPU; on CUDA run once eagerly (compiles), then capture and replay."""
    if not wp.get_device().is_cuda:
        return fn
    graph: list[Any] = []

    def run() -> None:
        if not graph:
            graph.append(None)
            fn()
            return
        if graph[0] is None:
            with wp.ScopedCapture() as capture:
                fn()
            graph[0] = capture.graph
        wp.capture_launch(graph[0])

    return run


def _simulate(
    wp: Any, mjw: Any, m: Any, d: Any, control: NDArray[np.float64], every: int, nstate: int
) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
    """Step every world through ``control``; state and sensordata, ``(nrec, nworld, n)``."""
    set_ctrl, record, advance = _kernels()
    nworld, nu, nsens = d.nworld, control.shape[1], d.sensordata.shape[1]
    nrec = len(control) // every
    ctrl_all = wp.array(control, dtype=float)
    step_no, row_no = wp.zeros(1, dtype=wp.int32), wp.zeros(1, dtype=wp.int32)
    scratch = wp.zeros((nworld, nstate), dtype=float)
    every_world = wp.ones(nworld, dtype=bool)  # get_state would allocate it per call
    state_out = wp.zeros((nrec, nworld, nstate), dtype=float)
    sens_out = wp.zeros((nrec, nworld, nsens), dtype=float)

    def one_step() -> None:
        if nu:
            wp.launch(set_ctrl, dim=(nworld, nu), inputs=[ctrl_all, step_no], outputs=[d.ctrl])
        mjw.step(m, d)
        wp.launch(advance, dim=1, inputs=[step_no])

    def one_record() -> None:
        mjw.get_state(m, d, scratch, _FULL, every_world)
        wp.launch(
            record,
            dim=nworld,
            inputs=[scratch, d.sensordata, row_no],
            outputs=[state_out, sens_out],
        )
        wp.launch(advance, dim=1, inputs=[row_no])

    step_fn, record_fn = _graphed(wp, one_step), _graphed(wp, one_record)
    for _ in range(nrec):
        for _ in range(every):
            step_fn()
        record_fn()
    wp.synchronize_device()
    return state_out.numpy(), sens_out.numpy()


def _valid_rows(state: NDArray[np.float64], nq: int, nv: int) -> NDArray[np.int64]:
    """Per world, the leading rows that are finite and within the divergence speed."""
    qvel = np.abs(state[:, :, 1 + nq : 1 + nq + nv])
    sane: NDArray[np.bool_] = np.all(np.isfinite(state), axis=2) & np.all(
        qvel <= DIVERGED_SPEED_RAD_S, axis=2
    )
    return np.where(sane.all(axis=1), sane.shape[1], np.argmin(sane, axis=1)).astype(np.int64)


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
    nconmax: int | None = None,
    njmax: int | None = None,
) -> WarpRollout:
    """Roll out every model from its state under one open-loop control sequence, batched.

    Args:
        models: one model per batch item, all compiled from the same MJCF; the fields in
            which they differ are given to MuJoCo Warp per world.
        initial_state: ``mjSTATE_FULLPHYSICS`` state, ``(nstate,)`` shared by all items or
            ``(nbatch, nstate)`` one each.
        control: ``(nstep, nu)`` ``ctrl`` for every step, shared by all items (actuator
            units, e.g. motor-side position setpoints [rad] for zmpkit's dcmotors).
        record_every: keep state and sensordata after every ``record_every``-th step;
            ``nstep % record_every`` trailing steps are not simulated.
        device: Warp device (``"cuda:0"``, ``"cpu"``); ``None`` is Warp's default.
        nconmax: contacts per world to allocate (MuJoCo Warp's default if ``None``).
        njmax: constraint rows per world to allocate (MuJoCo Warp's default if ``None``).

    Returns:
        The recorded rows: row ``k`` is after step ``(k + 1) * record_every``.

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
    state0, ctrl = _check_inputs(template, len(models), initial_state, control, record_every)
    state0 = np.broadcast_to(state0, (len(models), state0.shape[-1]))
    check_supported(mjw, template)
    fields = batched_fields(mjw, models)
    nbatch, nstate = state0.shape
    with wp.ScopedDevice(_device(wp, device)):
        m = put_models(wp, mjw, models, fields)
        d = mjw.put_data(
            template, mujoco.MjData(template), nworld=nbatch, nconmax=nconmax, njmax=njmax
        )
        mjw.set_state(m, d, wp.array(np.ascontiguousarray(state0), dtype=float), _FULL)
        state32, sens32 = _simulate(wp, mjw, m, d, ctrl, int(record_every), nstate)
        overflow = d.overflow.numpy()
        name = str(wp.get_device())
    state = np.ascontiguousarray(state32.transpose(1, 0, 2), dtype=np.float64)
    sens = np.ascontiguousarray(sens32.transpose(1, 0, 2), dtype=np.float64)
    valid = _valid_rows(state, template.nq, template.nv)
    steps = (np.arange(state.shape[1]) + 1) * int(record_every)
    timestep = np.array([mm.opt.timestep for mm in models])
    state[:, :, 0] = state0[:, :1] + timestep[:, None] * steps[None, :]
    capped = _overflow_check(mjw, overflow, valid == state.shape[1])
    return WarpRollout(state, sens, valid, capped, fields, name)
