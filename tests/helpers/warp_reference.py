"""The per-model loops that compared a batch's models before they were vectorised.

Kept as the reference the vectorised :func:`zmpkit.sim.warp_model._differing_fields` and
:func:`~zmpkit.sim.warp_model.per_world_values` are tested against (same fields, same
errors, same arrays), and timed against in ``benchmarks/bench_warp_fields.py``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.sim.warp_model import _SWITCH_FIELDS, _UNREAD_BY_WARP

__all__ = ["model_arrays", "reference_differing_fields", "reference_per_world_values"]


def model_arrays(model: mujoco.MjModel) -> dict[str, NDArray[Any]]:
    """Every numeric array of ``model`` and its options (as ``opt.<name>``)."""
    out: dict[str, NDArray[Any]] = {}
    for name in dir(model):
        value = getattr(model, name, None) if not name.startswith("_") else None
        if isinstance(value, np.ndarray):
            out[name] = value
    for name in dir(model.opt):
        value = getattr(model.opt, name) if not name.startswith("_") else None
        if isinstance(value, int | float | np.ndarray):
            out["opt." + name] = np.asarray(value)
    return out


def reference_differing_fields(
    models: Sequence[mujoco.MjModel], batchable: set[str]
) -> tuple[str, ...]:
    """The fields in which ``models`` differ: every model against the first, field by field."""
    arrays = [model_arrays(model) for model in models]
    differing: set[str] = set()
    for index, other in enumerate(arrays[1:], start=1):
        for name, value in arrays[0].items():
            if value.shape != other[name].shape:
                raise ParameterError(
                    f"models[{index}] differs from models[0] in the size of {name!r} "
                    f"({other[name].shape} vs {value.shape}); batch models of one MJCF"
                )
            if not np.array_equal(value, other[name], equal_nan=True):
                differing.add(name)
    differing -= _UNREAD_BY_WARP
    unbatchable = sorted(differing - batchable)
    if unbatchable:
        raise ParameterError(
            f"the models differ in {', '.join(map(repr, unbatchable))}, which MuJoCo Warp "
            f"cannot give per world; per-world fields: {sorted(batchable)}"
        )
    for name in sorted(differing & set(_SWITCH_FIELDS)):
        if any(not np.array_equal(arrays[0][name] == 0, a[name] == 0) for a in arrays[1:]):
            raise ParameterError(
                f"the models differ in which entries of {name!r} are zero; MuJoCo Warp "
                "chooses code paths from the first model, so batch models with the same zeros"
            )
    return tuple(sorted(differing))


def reference_per_world_values(
    models: Sequence[mujoco.MjModel], fields: Sequence[str]
) -> dict[str, NDArray[Any]]:
    """Each field stacked over the models, read model by model."""
    out = {}
    for name in fields:
        if name.startswith("opt."):
            out[name] = np.stack([np.asarray(getattr(m.opt, name[4:])) for m in models])
        else:
            out[name] = np.stack([np.asarray(getattr(m, name)) for m in models])
    return out
