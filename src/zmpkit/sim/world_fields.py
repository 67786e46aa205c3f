"""A batch of models as one compiled model plus per-world values of the fields that differ.

A fit's candidates are one MJCF with different numbers: instead of writing and compiling an
MJCF per candidate, the numbers are written straight into the fields of one compiled model
(the *template*), one row per world. :class:`FieldWrite` is one such write (entries of one
field, one row of values per world); :class:`WorldFields` is the template plus every
written field stacked over the worlds, what MuJoCo Warp puts per world
(:mod:`zmpkit.sim.warp_batch`).

A write to a mass, a CoM or an inertia (or an armature) also changes what MuJoCo derives
from them when it compiles (``mj_setConst``: :data:`SETCONST_FIELDS`): with
``derived=True`` those are recomputed per world by ``mj_setConst`` on a host copy of the
template, as the compiler computes them.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = ["SETCONST_FIELDS", "CandidateFields", "FieldWrite", "WorldFields"]

SETCONST_FIELDS = (
    "body_subtreemass",
    "body_invweight0",
    "dof_invweight0",
    "tendon_invweight0",
    "actuator_acc0",
    "dof_M0",
    "dof_length",
    "cam_poscom0",
    "light_poscom0",
)
"""Model fields ``mj_setConst`` derives from the masses, inertias and armatures (and the
compiler with it); the rest it sets depends on ``qpos0`` only, which no write changes."""


@dataclass(frozen=True)
class FieldWrite:
    """Entries of one model field, set per world.

    Attributes:
        field: the MjModel field, e.g. ``"tendon_stiffness"``.
        index: ``(k,)`` the entries written, flat indices into the field (C order).
        values: ``(nworld, k)`` the value of each entry in each world [the field's unit].
    """

    field: str
    index: NDArray[np.int64]
    values: NDArray[np.float64]

    @classmethod
    def of(cls, field: str, index: Sequence[int], values: NDArray[Any]) -> FieldWrite:
        """A write of ``values`` ``(nworld,)`` (one per world, every entry) or ``(nworld, k)``."""
        idx = np.asarray(index, dtype=np.int64).reshape(-1)
        vals = np.asarray(values, dtype=np.float64)
        vals = vals.reshape(-1, 1) if vals.ndim == 1 else vals
        return cls(field, idx, np.broadcast_to(vals, (vals.shape[0], idx.size)))


@dataclass(frozen=True)
class CandidateFields:
    """What a batch of candidates changes in a robot's compiled model and its readings.

    Attributes:
        writes: the model fields, one row per candidate.
        derived: the writes change a mass, CoM, inertia or armature, so the fields
            ``mj_setConst`` derives must be recomputed (:meth:`WorldFields.with_derived`).
        ft_offsets: foot -> ``(ncandidate, 6)`` its F-T sensor's offset (Fx, Fy, Fz, Tx,
            Ty, Tz) [N, N·m] (effect S, applied on the host); feet left out keep the
            robot description's.
    """

    writes: tuple[FieldWrite, ...]
    derived: bool = False
    ft_offsets: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)


@dataclass(frozen=True)
class WorldFields:
    """One compiled model and, per world, the values of the fields that differ.

    Attributes:
        template: the compiled model every world shares but for ``values``.
        values: field name -> ``(nworld, *shape)`` its value in each world.
        nworld: the number of worlds.
    """

    template: mujoco.MjModel
    values: Mapping[str, NDArray[Any]]
    nworld: int

    def __len__(self) -> int:
        return self.nworld

    @property
    def names(self) -> tuple[str, ...]:
        """The per-world fields, sorted."""
        return tuple(sorted(self.values))

    @classmethod
    def of_writes(
        cls,
        template: mujoco.MjModel,
        writes: Sequence[FieldWrite],
        nworld: int,
        derived: bool = False,
    ) -> WorldFields:
        """The template with ``writes`` applied per world.

        Args:
            template: the compiled model (left unchanged).
            writes: the fields to set per world (a later write of an entry wins).
            nworld: the number of worlds (every write's first dimension).
            derived: recompute :data:`SETCONST_FIELDS` per world with ``mj_setConst`` (a
                write changed a mass, CoM, inertia or armature).
        """
        values: dict[str, NDArray[np.float64]] = {}
        for write in writes:
            if write.values.shape[0] != nworld:
                raise ParameterError(
                    f"write of {write.field!r} has {write.values.shape[0]} worlds, "
                    f"expected {nworld}"
                )
            if write.field not in values:
                base = np.asarray(getattr(template, write.field), dtype=np.float64)
                values[write.field] = np.repeat(base[None], nworld, axis=0)
            flat = values[write.field].reshape(nworld, -1)
            flat[:, write.index] = write.values
        out = cls(template, values, nworld)
        return out.with_derived() if derived else out

    @classmethod
    def of_models(cls, models: Sequence[mujoco.MjModel], fields: Sequence[str]) -> WorldFields:
        """The first model as the template, ``fields`` stacked over ``models``."""
        values = {name: np.stack([_field(m, name) for m in models]) for name in fields}
        return cls(models[0], values, len(models))

    def write_into(self, model: mujoco.MjModel, world: int) -> None:
        """Set ``model``'s per-world fields (a copy of the template) to world ``world``'s."""
        for name, values in self.values.items():
            if name.startswith("opt."):
                setattr(model.opt, name[4:], values[world])
            else:
                getattr(model, name)[...] = values[world]

    def model(self, world: int) -> mujoco.MjModel:
        """A host copy of the template with world ``world``'s fields."""
        model = copy.copy(self.template)
        self.write_into(model, world)
        return model

    def with_derived(self) -> WorldFields:
        """These fields plus :data:`SETCONST_FIELDS`, recomputed per world by ``mj_setConst``."""
        model = copy.copy(self.template)
        data = mujoco.MjData(model)
        derived = {
            name: np.repeat(
                np.asarray(getattr(model, name), dtype=np.float64)[None], self.nworld, 0
            )
            for name in SETCONST_FIELDS
        }
        for world in range(self.nworld):
            self.write_into(model, world)
            mujoco.mj_setConst(model, data)
            for name, stack in derived.items():
                stack[world] = getattr(model, name)
        return WorldFields(self.template, {**self.values, **derived}, self.nworld)


def _field(model: mujoco.MjModel, name: str) -> NDArray[Any]:
    """``model``'s field ``name`` (``opt.<name>`` for an option) as an array."""
    if name.startswith("opt."):
        return np.asarray(getattr(model.opt, name[4:]))
    return np.asarray(getattr(model, name))
