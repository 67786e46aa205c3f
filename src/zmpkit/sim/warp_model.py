"""The per-world MuJoCo Warp model of a batch of MuJoCo models (one MJCF, other parameters).

The fields in which the models differ become per-world ("batched") MuJoCo Warp arrays; a
field Warp cannot hold per world, a model feature it lacks, or a difference in a field from
which it derives code paths (zero patterns) is a :class:`~zmpkit.errors.ParameterError`.

A batch whose per-world fields are already known (a fit's candidates written into one
compiled model, :class:`~zmpkit.sim.world_fields.WorldFields`) skips the comparison: its
fields are only checked (:func:`world_fields_for_warp`).

The comparison is vectorised over fields: each model's fields are read with one look-up per
dtype and compared with the first model's in one numpy operation (about 0.3 ms per model of
a 24-joint humanoid, 7 times faster than field by field; ``benchmarks/bench_warp_fields.py``).
"""

import dataclasses
import operator
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.sim.world_fields import WorldFields

__all__ = [
    "assign_per_world",
    "batched_fields",
    "check_supported",
    "model_differences",
    "per_world_values",
    "put_models",
    "size_key",
    "world_fields_for_warp",
]

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


@dataclass(frozen=True)
class _Group:
    """Fields of one dtype, read from a model (or its options) as one flat vector.

    Attributes:
        names: the fields, in the order of :func:`_model_arrays` (``opt.`` for options).
        bounds: ``(len(names) + 1,)`` offsets of each field in the flat vector.
        options: the fields are ``model.opt``'s.
        floating: the dtype is a float one (NaN equals NaN when comparing).
    """

    names: tuple[str, ...]
    bounds: NDArray[np.int64]
    options: bool
    floating: bool

    def flat(self, model: mujoco.MjModel) -> NDArray[Any]:
        """The fields of ``model`` flattened and joined, in their dtype (one look-up)."""
        if self.options:
            values = operator.attrgetter(*[n[4:] for n in self.names])(model.opt)
            return np.hstack(values if len(self.names) > 1 else (values,))
        values = operator.attrgetter(*self.names)(model)
        return np.concatenate(values if len(self.names) > 1 else (values,), axis=None)

    def per_field(self, mask: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """Per field, whether ``mask`` (over the flat vector) is set in any of its entries."""
        total = np.concatenate([[0], np.cumsum(mask, dtype=np.int64)])
        return np.asarray(total[self.bounds[1:]] > total[self.bounds[:-1]])


def _groups(arrays: dict[str, NDArray[Any]]) -> list[_Group]:
    """The fields of one model's :func:`_model_arrays`, grouped by dtype and kind."""
    keyed: dict[tuple[bool, str], list[str]] = {}
    for name, value in arrays.items():
        keyed.setdefault((name.startswith("opt."), value.dtype.str), []).append(name)
    groups = []
    for (options, _), names in keyed.items():
        sizes = [arrays[n].size for n in names]
        bounds = np.concatenate([[0], np.cumsum(sizes, dtype=np.int64)])
        floating = np.issubdtype(arrays[names[0]].dtype, np.floating)
        groups.append(_Group(tuple(names), bounds, options, bool(floating)))
    return groups


def _size_names(model: mujoco.MjModel) -> list[str]:
    """The sizes of ``model`` (``nq``, ``nv``, ``nbody``, ...): the ints named ``n...``."""
    return [n for n in dir(model) if n.startswith("n") and isinstance(getattr(model, n), int)]


def _raise_on_size(index: int, first: dict[str, NDArray[Any]], model: mujoco.MjModel) -> None:
    """Raise on the first field (in :func:`_model_arrays` order) whose shape differs."""
    for name, value in first.items():
        shape = _field(model, name).shape
        if value.shape != shape:
            raise ParameterError(
                f"models[{index}] differs from models[0] in the size of {name!r} "
                f"({shape} vs {value.shape}); batch models of one MJCF"
            )


def _differing_fields(models: Sequence[mujoco.MjModel], batchable: set[str]) -> tuple[str, ...]:
    """The fields in which ``models`` differ; each must be one Warp keeps per world.

    Vectorised over fields: each model's fields are read in one look-up per dtype, joined
    into one vector per dtype and compared with the first model's in one operation (NaN
    equal to NaN, as ``np.array_equal(..., equal_nan=True)``); the zero patterns likewise.
    The Python loop is over models only, a handful of numpy calls each.
    """
    first = _model_arrays(models[0])
    groups = _groups(first)
    sizes = operator.attrgetter(*_size_names(models[0]))
    sizes0 = sizes(models[0])
    reference = [g.flat(models[0]) for g in groups]
    nans = [np.isnan(r) if g.floating else None for g, r in zip(groups, reference, strict=True)]
    zeros = [r == 0 for r in reference]
    differ = [np.zeros(r.shape, dtype=bool) for r in reference]
    zeros_differ = [np.zeros(r.shape, dtype=bool) for r in reference]
    for index, model in enumerate(models[1:], start=1):
        if sizes(model) != sizes0:  # the array shapes are functions of the sizes
            _raise_on_size(index, first, model)
        for k, group in enumerate(groups):
            flat = group.flat(model)
            if flat.shape != reference[k].shape:
                _raise_on_size(index, first, model)
            unequal = flat != reference[k]
            nan0 = nans[k]
            if nan0 is not None:
                unequal &= ~(nan0 & np.isnan(flat))
            differ[k] |= unequal
            zeros_differ[k] |= (flat == 0) != zeros[k]
    differing: set[str] = set()
    zero_pattern: set[str] = set()
    for group, mask, zmask in zip(groups, differ, zeros_differ, strict=True):
        names = np.asarray(group.names)
        differing.update(names[group.per_field(mask)].tolist())
        zero_pattern.update(names[group.per_field(zmask)].tolist())
    differing -= _UNREAD_BY_WARP
    unbatchable = sorted(differing - batchable)
    if unbatchable:
        raise ParameterError(
            f"the models differ in {', '.join(map(repr, unbatchable))}, which MuJoCo Warp "
            f"cannot give per world; per-world fields: {sorted(batchable)}"
        )
    switched = sorted(differing & set(_SWITCH_FIELDS) & zero_pattern)
    if switched:
        raise ParameterError(
            f"the models differ in which entries of {switched[0]!r} are zero; MuJoCo Warp "
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


def per_world_values(
    models: Sequence[mujoco.MjModel], fields: Sequence[str]
) -> dict[str, NDArray[Any]]:
    """Each of ``fields`` stacked over ``models``: ``(len(models), *shape)``, one stack each."""
    return {name: np.stack([_field(model, name) for model in models]) for name in fields}


def put_models(wp: Any, mjw: Any, worlds: WorldFields) -> Any:
    """The Warp model of ``worlds.template`` with ``worlds``'s fields given per world."""
    model_fields = [f for f in worlds.values if not f.startswith("opt.")]
    try:
        m = mjw.put_model(worlds.template, batch_sizes=dict.fromkeys(model_fields, len(worlds)))
    except NotImplementedError as exc:
        raise ParameterError(
            f"MuJoCo Warp does not support this model: {exc}; "
            "run it on the CPU (the fit's backend 'local', or mujoco.rollout)"
        ) from exc
    m.opt.warn_overflow = 0  # overflows are read from Data.overflow and raised below
    assign_per_world(wp, m, worlds)
    return m


def assign_per_world(wp: Any, m: Any, worlds: WorldFields) -> None:
    """Copy each of ``worlds``'s per-world fields into the Warp model ``m``.

    Arrays that already hold one row per world are written in place (a captured graph
    that reads them stays valid); an option still shared by all worlds is replaced by a
    per-world array.
    """
    for name, values in worlds.values.items():
        if name.startswith("opt."):
            current = getattr(m.opt, name[4:])
            if current.shape[0] == len(worlds):
                current.assign(wp.array(values, dtype=current.dtype))
            else:
                setattr(m.opt, name[4:], wp.array(values, dtype=current.dtype))
        else:
            array = getattr(m, name)
            shape = array.shape + getattr(array.dtype, "_shape_", ())
            array.assign(wp.array(values.reshape(shape), dtype=array.dtype))


def size_key(model: mujoco.MjModel) -> tuple[int, ...]:
    """``model``'s sizes (``nq``, ``nv``, ...): models with the same have the same layout."""
    return tuple(operator.attrgetter(*_size_names(model))(model))


def model_differences(model: mujoco.MjModel, other: mujoco.MjModel, allowed: Sequence[str]) -> bool:
    """Whether ``other`` differs from ``model`` beyond the values of the ``allowed`` fields.

    A different size, a field outside ``allowed`` or a zero pattern of a field from which
    MuJoCo Warp derives code paths counts; a Warp model of ``model`` with ``allowed`` per
    world serves ``other`` if this is False.
    """
    try:
        _differing_fields([model, other], set(allowed))
    except ParameterError:
        return True
    return False


def world_fields_for_warp(mjw: Any, worlds: WorldFields) -> WorldFields:
    """``worlds`` without the fields MuJoCo Warp never reads, checked as :func:`batched_fields`.

    Raises:
        ParameterError: a per-world field Warp cannot batch, or one of the fields from
            whose zero pattern Warp derives code paths with another zero pattern than the
            template's.
    """
    kept = {k: v for k, v in worlds.values.items() if k not in _UNREAD_BY_WARP}
    batchable = _batchable(mjw)
    unbatchable = sorted(set(kept) - batchable)
    if unbatchable:
        raise ParameterError(
            f"the models differ in {', '.join(map(repr, unbatchable))}, which MuJoCo Warp "
            f"cannot give per world; per-world fields: {sorted(batchable)}"
        )
    for name in sorted(set(kept) & set(_SWITCH_FIELDS)):
        zeros = _field(worlds.template, name) == 0
        if np.any((kept[name] == 0) != zeros[None]):
            raise ParameterError(
                f"the models differ in which entries of {name!r} are zero; MuJoCo Warp "
                "chooses code paths from the first model, so batch models with the same zeros"
            )
    return WorldFields(worlds.template, kept, worlds.nworld)


def batched_fields(mjw: Any, models: Sequence[mujoco.MjModel]) -> tuple[str, ...]:
    """The fields in which ``models`` differ, each one MuJoCo Warp ``mjw`` keeps per world.

    Raises:
        ParameterError: a differing field Warp cannot batch, or a different zero pattern.
    """
    return _differing_fields(models, _batchable(mjw))
