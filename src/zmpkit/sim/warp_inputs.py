"""The checks of a batched Warp rollout's inputs: states, controls, recorded steps and arrays.

Pure numpy (no Warp): :func:`~zmpkit.sim.warp_batch.rollout_warp` checks its arguments here
before it starts a device, so a bad call fails fast with a
:class:`~zmpkit.errors.ParameterError` naming what was expected.
"""

from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = ["RECORDABLE", "check_inputs", "check_records", "record_steps"]

_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)
RECORDABLE = ("state", "qpos", "qvel", "act", "sensordata", "site_xpos", "site_xmat")
"""What :func:`~zmpkit.sim.warp_batch.rollout_warp` can record per row: the
``mjSTATE_FULLPHYSICS`` state, or the named ``mjData`` arrays (``site_xpos`` as
``(nsite * 3)``, ``site_xmat`` as ``(nsite * 9)``)."""


def check_inputs(
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


def record_steps(
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


def check_records(record: Sequence[str], steps_per_launch: int) -> tuple[str, ...]:
    """The names to record, checked with the steps per launch (an integer >= 1)."""
    names = tuple(record)
    if not names or len(set(names)) != len(names) or not set(names) <= set(RECORDABLE):
        raise ParameterError(f"record must name distinct arrays among {RECORDABLE}, got {names!r}")
    if isinstance(steps_per_launch, bool) or not isinstance(steps_per_launch, int | np.integer):
        raise ParameterError(f"steps_per_launch must be an integer >= 1, got {steps_per_launch!r}")
    if steps_per_launch < 1:
        raise ParameterError(f"steps_per_launch must be an integer >= 1, got {steps_per_launch!r}")
    return names
