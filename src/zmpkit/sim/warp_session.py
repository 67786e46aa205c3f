"""The device state a batched rollout keeps between calls (:mod:`zmpkit.sim.warp_batch`).

A fit runs one batch per generation with the same robot, candidates count and rollout
length, so what is costly to make is kept: per batch layout a *session* (the MuJoCo Warp
model, with the candidates' differing fields per world, and its data), and per session a
few *plans* (the device buffers of one rollout length and set of records, and on CUDA the
graphs captured for them). A later call of the same layout only copies the new
candidates' per-world fields in. Both caches are small and least-recently-used first:
:data:`MAX_SESSIONS` sessions, :data:`MAX_PLANS` plans each (device memory: one batch
each). :func:`clear_warp_cache` releases them.
"""

from __future__ import annotations

import copy
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from zmpkit.sim.warp_columns import PER_COLUMN
from zmpkit.sim.warp_model import assign_per_world, model_differences, put_models, size_key
from zmpkit.sim.world_fields import WorldFields

__all__ = [
    "MAX_PLANS",
    "MAX_SESSIONS",
    "Plan",
    "Session",
    "SquarePlan",
    "clear_warp_cache",
    "plan_for",
    "session_for",
]

MAX_SESSIONS = 4
"""Warp models and data kept between calls (device memory: one batch each)."""
MAX_PLANS = 4
"""Buffer and graph sets kept per model and data (one per rollout length and records)."""
_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)


@dataclass(frozen=True)
class Plan:
    """Device buffers (and, on CUDA, graphs) of one rollout length and set of records.

    ``graphs`` (steps per launch -> captured graph) fills on first use.
    """

    control: Any
    group: Any
    row_of_step: Any
    counter: Any
    first_bad: Any
    outputs: dict[str, Any]
    columns: dict[str, Any]
    scratch: Any
    every_world: Any
    square: SquarePlan | None
    graphs: dict[int, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class SquarePlan:
    """Device buffers of a :class:`QposSquareError`."""

    columns: Any
    quantum: Any
    row_of_step: Any
    target: Any
    total: Any


@dataclass(frozen=True)
class Session:
    """A Warp model and data of one batch layout, kept between calls, with its plans."""

    template: mujoco.MjModel
    fields: tuple[str, ...]
    m: Any
    d: Any
    plans: OrderedDict[tuple[Any, ...], Plan] = field(default_factory=OrderedDict)


_SESSIONS: OrderedDict[tuple[Any, ...], Session] = OrderedDict()
"""This process's Warp models and data, least recently used first."""


def clear_warp_cache() -> None:
    """Release the Warp models, data, buffers and graphs kept between calls."""
    _SESSIONS.clear()


def session_for(
    wp: Any,
    mjw: Any,
    worlds: WorldFields,
    device: str,
    nconmax: int | None,
    njmax: int | None,
) -> Session:
    """The cached Warp model and data for ``worlds`` (built on a miss), per-world fields set."""
    template, fields = worlds.template, worlds.names
    key = (device, size_key(template), fields, len(worlds), nconmax, njmax)
    session = _SESSIONS.get(key)
    if session is not None and not model_differences(session.template, template, fields):
        _SESSIONS.move_to_end(key)
        assign_per_world(wp, session.m, worlds)
        return session
    m = put_models(wp, mjw, worlds)
    d = mjw.put_data(
        template, mujoco.MjData(template), nworld=len(worlds), nconmax=nconmax, njmax=njmax
    )
    session = Session(copy.deepcopy(template), fields, m, d)
    _SESSIONS[key] = session
    _SESSIONS.move_to_end(key)
    while len(_SESSIONS) > MAX_SESSIONS:
        _SESSIONS.popitem(last=False)
    return session


def plan_for(
    wp: Any,
    session: Session,
    ngroup: int,
    nstep: int,
    nrec: int,
    columns: dict[str, tuple[int, ...]],
    square_shape: tuple[int, int] | None,
) -> Plan:
    """The cached buffers for ``ngroup`` control sequences of ``nstep`` steps, ``nrec`` rows.

    ``square_shape``: (target rows, columns) of a :class:`QposSquareError`, or None.
    """
    template, nworld = session.template, session.d.nworld
    key = (ngroup, nstep, nrec, tuple(columns.items()), square_shape)
    plan = session.plans.get(key)
    if plan is not None:
        session.plans.move_to_end(key)
        return plan
    nstate = mujoco.mj_stateSize(template, _FULL)
    square = None
    if square_shape is not None:
        rows, j = square_shape
        square = SquarePlan(
            columns=wp.zeros(j, dtype=wp.int32),
            quantum=wp.zeros(j, dtype=wp.float64),
            row_of_step=wp.zeros((ngroup, nstep), dtype=wp.int32),
            target=wp.zeros((ngroup, rows, j), dtype=wp.float64),
            total=wp.zeros(nworld, dtype=wp.float64),
        )
    plan = Plan(
        control=wp.zeros((ngroup, nstep, max(template.nu, 1)), dtype=float),
        group=wp.zeros(nworld, dtype=wp.int32),
        row_of_step=wp.zeros(nstep, dtype=wp.int32),
        counter=wp.zeros(1, dtype=wp.int32),
        first_bad=wp.zeros(nworld, dtype=wp.int32),
        outputs={
            name: wp.zeros((nrec, nworld, len(cols) * PER_COLUMN.get(name, 1)), dtype=float)
            for name, cols in columns.items()
        },
        columns={
            name: wp.array(np.asarray(cols, dtype=np.int32), dtype=wp.int32)
            for name, cols in columns.items()
        },
        scratch=wp.zeros((nworld, nstate), dtype=float) if "state" in columns else None,
        every_world=wp.ones(nworld, dtype=bool),  # get_state would allocate it per call
        square=square,
    )
    session.plans[key] = plan
    while len(session.plans) > MAX_PLANS:
        session.plans.popitem(last=False)
    return plan
