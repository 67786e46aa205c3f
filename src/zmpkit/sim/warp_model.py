"""The per-world MuJoCo Warp model of a batch of MuJoCo models (one MJCF, other parameters).

The fields in which the models differ become per-world ("batched") MuJoCo Warp arrays; a
field Warp cannot hold per world, a model feature it lacks, or a difference in a field from
which it derives code paths (zero patterns) is a :class:`~zmpkit.errors.ParameterError`.
"""

import dataclasses
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = ["batched_fields", "check_supported", "put_models"]

_OPTION_BATCHABLE = ("timestep", "gravity", "magnetic")
"""``opt`` fields that MuJoCo Warp keeps per world and copies unchanged."""
_UNREAD_BY_WARP = frozenset({"dof_M0", "dof_length"})
"""Model fields mujoco_warp 4.0.0 never reads (derived by ``mj_setConst``; ``dof_length``
only by sleeping, which zmpkit's models leave off); may differ."""
_SWITCH_FIELDS = (
    "tendon_stiffness",
    "tendon_stiffnesspoly",
    "tendon_damping",
    "tendon_dampingpoly",
    "actuator_gainprm",
    "actuator_biasprm",
    "actuator_damping",
    "actuator_dampingpoly",
    "actuator_gear",
)
"""Fields from whose zero pattern ``mujoco_warp.put_model`` derives code-path switches
(``has_tendon_stiffness``, ``has_tendon_damping``, ``has_efm_actuator``, ...) from the first
model only; their zero pattern must be the same in every model."""


def _model_arrays(model: mujoco.MjModel) -> dict[str, NDArray[Any]]:
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


def _differing_fields(models: Sequence[mujoco.MjModel], batchable: set[str]) -> tuple[str, ...]:
    """The fields in which ``models`` differ; each must be one Warp keeps per world."""
    arrays = [_model_arrays(model) for model in models]
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


def _batchable(mjw: Any) -> set[str]:
    """Model fields MuJoCo Warp can hold per world (leading ``*`` dimension) and options."""
    fields = dataclasses.fields(mjw.Model)
    per_world = {f.name for f in fields if getattr(f.type, "shape", ())[:1] == ("*",)}
    return per_world | {"opt." + n for n in _OPTION_BATCHABLE}


def check_supported(mjw: Any, model: mujoco.MjModel) -> None:
    """Raise a ParameterError naming the element types MuJoCo Warp lacks.

    Covers actuators and geoms; the rest (sensors, equalities, options) is checked by
    ``mujoco_warp.put_model``, whose error is wrapped in :func:`put_models`.
    """
    for field, kind, enum in (
        ("actuator_trntype", mjw.TrnType, mujoco.mjtTrn),
        ("actuator_dyntype", mjw.DynType, mujoco.mjtDyn),
        ("actuator_gaintype", mjw.GainType, mujoco.mjtGain),
        ("actuator_biastype", mjw.BiasType, mujoco.mjtBias),
        ("geom_type", mjw.GeomType, mujoco.mjtGeom),
    ):
        known = {int(k) for k in kind}
        missing = sorted({enum(int(v)).name for v in getattr(model, field) if int(v) not in known})
        if missing:
            raise ParameterError(
                f"MuJoCo Warp does not support {field} {missing}; "
                "run this model on the CPU (the fit's backend 'local', or mujoco.rollout)"
            )


def _field(model: mujoco.MjModel, name: str) -> NDArray[Any]:
    """``model``'s field ``name`` (``opt.<name>`` for an option) as an array."""
    if name.startswith("opt."):
        return np.asarray(getattr(model.opt, name[4:]))
    return np.asarray(getattr(model, name))


def put_models(wp: Any, mjw: Any, models: Sequence[mujoco.MjModel], fields: Sequence[str]) -> Any:
    """The Warp model of ``models[0]`` with ``fields`` given per world."""
    model_fields = [f for f in fields if not f.startswith("opt.")]
    try:
        m = mjw.put_model(models[0], batch_sizes={f: len(models) for f in model_fields})
    except NotImplementedError as exc:
        raise ParameterError(
            f"MuJoCo Warp does not support this model: {exc}; "
            "run it on the CPU (the fit's backend 'local', or mujoco.rollout)"
        ) from exc
    m.opt.warn_overflow = 0  # overflows are read from Data.overflow and raised below
    for name in fields:
        values = np.stack([_field(model, name) for model in models])
        if name.startswith("opt."):
            dtype = getattr(m.opt, name[4:]).dtype
            setattr(m.opt, name[4:], wp.array(values, dtype=dtype))
        else:
            array = getattr(m, name)
            shape = array.shape + getattr(array.dtype, "_shape_", ())
            array.assign(wp.array(values.reshape(shape), dtype=array.dtype))
    return m


def batched_fields(mjw: Any, models: Sequence[mujoco.MjModel]) -> tuple[str, ...]:
    """The fields in which ``models`` differ, each one MuJoCo Warp ``mjw`` keeps per world.

    Raises:
        ParameterError: a differing field Warp cannot batch, or a different zero pattern.
    """
    return _differing_fields(models, _batchable(mjw))
