"""Which columns a MuJoCo Warp rollout keeps, and the qpos error sum it accumulates.

Pure numpy (no Warp): :func:`~zmpkit.sim.warp_batch.rollout_warp` checks and lays out its
``columns`` and ``square_error`` arguments here, and CI tests them without MuJoCo Warp.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = [
    "PER_COLUMN",
    "QposSquareError",
    "all_columns",
    "check_square_error",
    "record_columns",
]

_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)


def all_columns(model: mujoco.MjModel, name: str) -> int:
    """Columns of the recordable ``name`` a row can keep: entries, or sites [-]."""
    widths = {
        "state": mujoco.mj_stateSize(model, _FULL),
        "qpos": model.nq,
        "qvel": model.nv,
        "act": model.na,
        "sensordata": model.nsensordata,
        "site_xpos": model.nsite,
        "site_xmat": model.nsite,
    }
    return widths[name]


PER_COLUMN = {"site_xpos": 3, "site_xmat": 9}
"""Recorded values per selected column (a site's position, its rotation matrix)."""


def record_columns(
    model: mujoco.MjModel, records: tuple[str, ...], columns: Mapping[str, Sequence[int]] | None
) -> dict[str, tuple[int, ...]]:
    """Per record, the columns (entries, or sites for the site kinematics) each row keeps.

    Args:
        model: the batch's model.
        records: the names recorded (:data:`~zmpkit.sim.warp_batch.RECORDABLE`).
        columns: the columns asked for per name; a name left out keeps every column.

    Raises:
        ParameterError: a name not recorded (or ``state``), or columns out of range.
    """
    chosen = dict(columns or {})
    unknown = sorted(set(chosen) - (set(records) - {"state"}))
    if unknown:
        raise ParameterError(
            f"columns names {unknown}, which are not recorded (or 'state', which keeps every "
            f"column); recorded: {list(records)}"
        )
    out = {}
    for name in records:
        size = all_columns(model, name)
        picked = tuple(int(c) for c in chosen.get(name, range(size)))
        if name in chosen and (not picked or min(picked) < 0 or max(picked) >= size):
            raise ParameterError(
                f"columns[{name!r}] must be a non-empty list of columns in [0, {size}), "
                f"got {list(chosen[name])!r}"
            )
        out[name] = picked
    return out


@dataclass(frozen=True)
class QposSquareError:
    r"""A sum of squared qpos errors against targets, accumulated per world on the device.

    For a world running control group :math:`g`, with target rows :math:`y_{g,k}` at steps
    :math:`s_{g,k}`:

    .. math:: S = \sum_k \sum_j \bigl(Q_j(q_{c_j}(s_{g,k})) - y_{g,k,j}\bigr)^2

    where :math:`Q_j` rounds to a multiple of ``quantum[j]`` (an encoder; 0 leaves it exact)
    and a NaN target leaves its term out (a column a group does not compare). The float32
    ``qpos`` is widened to float64 before it is quantised; the sum is float64.

    Attributes:
        columns: ``(J,)`` the qpos columns compared [-].
        steps: per control group, ``(R_g,)`` the steps (1 is after the first) of its target
            rows, increasing.
        targets: per control group, ``(R_g, J)`` the targets [qpos units, rad for hinges];
            NaN where not compared.
        quantum: ``(J,)`` each column's quantisation step [qpos units]; 0 = exact.
    """

    columns: tuple[int, ...]
    steps: tuple[NDArray[np.int64], ...]
    targets: tuple[NDArray[np.float64], ...]
    quantum: tuple[float, ...]

    def row_of_step(self, nstep: int) -> NDArray[np.int32]:
        """``(ngroup, nstep)`` each group's target row after each step, or -1."""
        table = np.full((len(self.steps), nstep), -1, dtype=np.int32)
        for g, steps in enumerate(self.steps):
            table[g, np.asarray(steps) - 1] = np.arange(len(steps), dtype=np.int32)
        return table

    def padded_targets(self) -> NDArray[np.float64]:
        """``(ngroup, max R_g, J)`` the targets, zero past each group's last row."""
        rows = max(len(t) for t in self.targets)
        out = np.zeros((len(self.targets), max(rows, 1), len(self.columns)))
        for g, target in enumerate(self.targets):
            out[g, : len(target)] = target
        return out


def check_square_error(
    square_error: QposSquareError | None, model: mujoco.MjModel, ngroup: int, nstep: int
) -> None:
    """Raise :class:`~zmpkit.errors.ParameterError` unless ``square_error`` fits the batch.

    Args:
        square_error: the sum asked for, or None (nothing to check).
        model: the batch's model.
        ngroup: control sequences of the batch.
        nstep: steps simulated.
    """
    if square_error is None:
        return
    se = square_error
    j = len(se.columns)
    if j == 0 or min(se.columns) < 0 or max(se.columns) >= model.nq or len(se.quantum) != j:
        raise ParameterError(
            f"square_error needs qpos columns in [0, nq={model.nq}) and one quantum each, "
            f"got columns {list(se.columns)} and {len(se.quantum)} quanta"
        )
    if len(se.steps) != ngroup or len(se.targets) != ngroup:
        raise ParameterError(
            f"square_error needs steps and targets for each of the {ngroup} control groups, "
            f"got {len(se.steps)} and {len(se.targets)}"
        )
    for steps, target in zip(se.steps, se.targets, strict=True):
        steps = np.asarray(steps)
        if (
            steps.ndim != 1
            or np.shape(target) != (len(steps), j)
            or (len(steps) and (steps.min() < 1 or steps.max() > nstep))
            or np.any(np.diff(steps) <= 0)
        ):
            raise ParameterError(
                f"square_error's steps must increase within [1, nstep={nstep}] (the steps "
                f"simulated), with a target row of {j} values each"
            )
