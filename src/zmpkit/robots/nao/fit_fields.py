"""The virtual NAO's fit parameters written into its compiled model (a :class:`FieldRule`).

Read as :mod:`zmpkit.robots.nao.truth` reads the truth file and applied as
:func:`~zmpkit.robots.nao.robot.nao_mjcf` applies it, with the fitted numbers as columns
(one value per candidate):

- **M** (on): ``stiffness`` and ``pid_volts.{p,i,d}`` -> every driven joint's controller
  gains (:func:`~zmpkit.robots.nao.truth.link_gains`, then
  :func:`~zmpkit.sim.builder.dcmotor_controller`); ``friction.coulomb_link`` -> its
  ``frictionloss``; with **I** on, ``motor.inductance`` -> its ``L/R``.
- **G** (on): ``gear.{stiffness,damping,backlash}`` -> every gear tendon.
- **F** (on): ``flex[*].stiffness[0]`` and ``flex[*].damping`` -> the flexible joints
  (polynomial springs only; NAO's truth has no softening spring).
- **S**: ``sensors.ft_offset.<side>[*]`` -> the feet's F-T offsets (host only).
- **C**: ``torso.mass_kg`` and ``torso.com_m[*]`` -> the torso's inertial (its inertia
  scaled with the mass, :func:`~zmpkit.robots.nao.truth.torso_inertia`), and what
  ``mj_setConst`` derives from it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import mujoco
import numpy as np

from zmpkit.robots.field_rule import (
    FieldRule,
    column,
    flex_doc_writes,
    ft_offset_columns,
    gear_doc_writes,
    item,
)
from zmpkit.robots.nao.model import NAO_DRIVEN_JOINTS, NAO_SIDES
from zmpkit.robots.nao.truth import link_gains, torso_inertia
from zmpkit.sim.builder import dcmotor_controller
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.effect_fields import (
    dcmotor_writes,
    frictionloss_writes,
    inertial_writes,
)
from zmpkit.sim.world_fields import CandidateFields, FieldWrite

__all__ = ["NAO_FIELD_RULE"]

TORSO_BODY = "torso"
"""The body whose inertial the ``torso`` section sets."""


def _motor_writes(model: mujoco.MjModel, doc: Mapping[str, Any], n: int) -> list[FieldWrite]:
    spec, pid, ratios = doc["motor"], doc["pid_volts"], doc["joints"]
    k, r = float(spec["torque_constant"]), float(spec["resistance"])
    s = item(doc["stiffness"])
    gains: list[list[Any]] = [[], [], []]
    for joint in NAO_DRIVEN_JOINTS:
        ratio = float(ratios[joint])
        kp, ki, kd = link_gains(s, k, ratio, r, pid)
        controller = dcmotor_controller(
            kp, ki, kd, ratio, k, r, False, float(pid["integral_limit_link"]), 0.0
        )
        for g in range(3):
            gains[g].append(column(controller[g], n))
    columns = (np.stack(gains[0], 1), np.stack(gains[1], 1), np.stack(gains[2], 1))
    coulomb = column(doc["friction"]["coulomb_link"], n)
    return [
        *dcmotor_writes(model, NAO_DRIVEN_JOINTS, gains=columns),
        *frictionloss_writes(model, NAO_DRIVEN_JOINTS, coulomb),
    ]


def _inductance_writes(model: mujoco.MjModel, doc: Mapping[str, Any], n: int) -> list[FieldWrite]:
    spec = doc["motor"]
    ohms, henry = column(spec["resistance"], n), column(spec["inductance"], n)
    return dcmotor_writes(model, NAO_DRIVEN_JOINTS, resistance=ohms, inductance=henry)


def _torso_writes(model: mujoco.MjModel, doc: Mapping[str, Any], n: int) -> list[FieldWrite]:
    torso = doc["torso"]
    mass = column(torso["mass_kg"], n)
    com = np.stack([column(v, n) for v in torso["com_m"]], 1)
    inertia = np.stack([column(v, n) for v in torso_inertia(mass)], 1)
    return inertial_writes(model, TORSO_BODY, mass, com, inertia)


def _write(
    model: mujoco.MjModel, description: RobotDescription, doc: Mapping[str, Any], n: int
) -> CandidateFields:
    effects = description.effects
    writes: list[FieldWrite] = []
    if effects.motor:
        writes += _motor_writes(model, doc, n)
        if effects.inductance:
            writes += _inductance_writes(model, doc, n)
    if effects.gear:
        writes += gear_doc_writes(model, NAO_DRIVEN_JOINTS, doc["gear"], n)
    if effects.flex:
        writes += flex_doc_writes(model, doc["flex"], n)
    writes += _torso_writes(model, doc, n)
    torso = doc["torso"]
    fitted = [torso["mass_kg"], *torso["com_m"]]
    derived = any(isinstance(v, np.ndarray) for v in fitted)  # else the template's
    ft = ft_offset_columns(doc["sensors"]["ft_offset"], NAO_SIDES, n)
    return CandidateFields(tuple(writes), derived=derived, ft_offsets=ft)


NAO_FIELD_RULE = FieldRule(
    paths=(
        "stiffness",
        "pid_volts.[pid]",
        "friction.coulomb_link",
        "motor.inductance",
        "gear.stiffness",
        "gear.damping",
        "gear.backlash",
        "flex[[]*].stiffness[[]0]",
        "flex[[]*].damping",
        "sensors.ft_offset.*",
        "torso.mass_kg",
        "torso.com_m*",
    ),
    write=_write,
)
"""The virtual NAO's :class:`~zmpkit.robots.field_rule.FieldRule` (module docstring)."""
