"""The virtual TEO's fit parameters written into its compiled model (a :class:`FieldRule`).

Read as :mod:`zmpkit.robots.teo.truth` reads the truth file and applied as
:func:`~zmpkit.robots.teo.robot.teo_mjcf` applies it, with the fitted numbers as columns
(one value per candidate):

- **M** (on): ``pid.{kp,ki,kd}_link`` -> every driven joint's controller
  (:func:`~zmpkit.sim.builder.dcmotor_controller`, its motor type's K and R, its ratio);
  ``friction.coulomb_link`` -> its ``frictionloss``; with **I** on,
  ``motor_types.<type>.inductance`` -> the ``L/R`` of that type's joints.
- **G** (on): ``gear.{stiffness,damping,backlash}`` -> the gear tendons of ``gear.joints``.
- **F** (on): ``flex[*].{stiffness[0],damping,softening_torque}`` -> the flexible joints,
  a softening spring's stage tendons included.
- **S**: ``sensors.ft_offset.<side>[*]`` -> the feet's F-T offsets (host only).
- **C**: ``payload.mass_kg`` and ``payload.position_m[*]`` -> the payload body's mass and
  position, and what ``mj_setConst`` derives from them.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import mujoco
import numpy as np

from zmpkit.robots.field_rule import FieldRule, column, ft_offset_columns, gear_doc_writes, item
from zmpkit.robots.teo.model import TEO_DRIVEN_JOINTS, TEO_SIDES
from zmpkit.sim.builder import dcmotor_controller
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.effect_fields import (
    dcmotor_writes,
    flex_writes,
    frictionloss_writes,
    mjcf_number,
    softening_flex_writes,
)
from zmpkit.sim.world_fields import CandidateFields, FieldWrite

__all__ = ["TEO_FIELD_RULE"]

PAYLOAD_BODY = "payload"
"""The body the ``payload`` section places in the trunk."""


def _motor_writes(
    model: mujoco.MjModel, doc: Mapping[str, Any], inductance: bool, n: int
) -> list[FieldWrite]:
    types, joints, pid = doc["motor_types"], doc["joints"], doc["pid"]
    writes: list[FieldWrite] = []
    for joint in TEO_DRIVEN_JOINTS:
        spec, ratio = types[joints[joint]["motor"]], joints[joint]["gear_ratio"]
        controller = dcmotor_controller(
            item(pid["kp_link"]),
            item(pid["ki_link"]),
            item(pid["kd_link"]),
            ratio,
            spec["torque_constant"],
            spec["resistance"],
            False,
            pid["integral_limit_link"],
            spec["voltage_limit"],
        )
        gains = (column(controller[0], n), column(controller[1], n), column(controller[2], n))
        writes += dcmotor_writes(
            model,
            [joint],
            gains=gains,
            resistance=column(spec["resistance"], n) if inductance else None,
            inductance=column(spec["inductance"], n) if inductance else None,
        )
    coulomb = column(doc["friction"]["coulomb_link"], n)
    return [*writes, *frictionloss_writes(model, TEO_DRIVEN_JOINTS, coulomb)]


def _flex_writes(model: mujoco.MjModel, doc: Mapping[str, Any], n: int) -> list[FieldWrite]:
    writes: list[FieldWrite] = []
    for entry in doc["flex"]:
        name, damping = str(entry["name"]), column(entry.get("damping", 0.0), n)
        k0, ts = column(entry["stiffness"][0], n), entry.get("softening_torque", 0.0)
        if isinstance(ts, np.ndarray) or float(ts) != 0.0:
            writes += softening_flex_writes(
                model,
                name,
                k0,
                column(ts, n),
                column(entry.get("softening_torque_range", 50.0), n),
                int(entry.get("softening_stages", 6)),
                damping,
            )
        else:
            writes += flex_writes(model, [name], k0, damping)
    return writes


def _payload_writes(model: mujoco.MjModel, doc: Mapping[str, Any], n: int) -> list[FieldWrite]:
    payload = doc["payload"]
    body = int(model.body(PAYLOAD_BODY).id)
    position = np.stack([column(v, n) for v in payload["position_m"]], 1)
    return [
        FieldWrite.of("body_mass", [body], mjcf_number(column(payload["mass_kg"], n))),
        FieldWrite.of("body_pos", [3 * body, 3 * body + 1, 3 * body + 2], mjcf_number(position)),
    ]


def _write(
    model: mujoco.MjModel, description: RobotDescription, doc: Mapping[str, Any], n: int
) -> CandidateFields:
    effects = description.effects
    writes: list[FieldWrite] = []
    if effects.motor:
        writes += _motor_writes(model, doc, effects.inductance, n)
    if effects.gear:
        gear = doc["gear"]
        writes += gear_doc_writes(model, tuple(gear.get("joints", doc["joints"])), gear, n)
    if effects.flex:
        writes += _flex_writes(model, doc, n)
    writes += _payload_writes(model, doc, n)
    payload = doc["payload"]
    derived = any(isinstance(v, np.ndarray) for v in (payload["mass_kg"], *payload["position_m"]))
    ft = ft_offset_columns(doc["sensors"]["ft_offset"], TEO_SIDES, n)
    return CandidateFields(tuple(writes), derived=derived, ft_offsets=ft)


TEO_FIELD_RULE = FieldRule(
    paths=(
        "pid.k[pid]_link",
        "friction.coulomb_link",
        "motor_types.*.inductance",
        "gear.stiffness",
        "gear.damping",
        "gear.backlash",
        "flex[[]*].stiffness[[]0]",
        "flex[[]*].damping",
        "flex[[]*].softening_torque",
        "sensors.ft_offset.*",
        "payload.mass_kg",
        "payload.position_m*",
    ),
    write=_write,
)
"""The virtual TEO's :class:`~zmpkit.robots.field_rule.FieldRule` (module docstring)."""
