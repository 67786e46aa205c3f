"""A servo-truth robot's fit parameters written into its compiled model (a :class:`FieldRule`).

For the robots whose truth has the layout of :mod:`zmpkit.robots.servo_truth` (the OP3, a
user's ``robot.yaml`` with ``truth:``), read as that module reads it and applied as
:func:`~zmpkit.robots.servo_truth.apply_servo_effects` applies it to every driven joint,
with the fitted numbers as columns (one value per candidate):

- **M** (on): ``pid.{kp,ki,kd}``, ``motor.resistance`` (a voltage drive's ``K²/R`` in kd) ->
  the controller (:func:`~zmpkit.sim.builder.dcmotor_controller`) and the ``dcmotor``'s
  resistance; ``friction.viscous_motor`` -> its damping; ``friction.coulomb_link`` -> the
  joint's ``frictionloss``; with **I** on, ``motor.inductance`` -> ``L/R``.
- **G** (on): ``gear.{stiffness,damping,backlash}`` -> every gear tendon.
- **F** (on): ``flex[*].stiffness[0]`` and ``flex[*].damping`` -> the flexible joints
  (polynomial springs only).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import mujoco

from zmpkit.robots.field_rule import FieldRule, column, flex_doc_writes, gear_doc_writes, item
from zmpkit.sim.builder import dcmotor_controller
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.effect_fields import dcmotor_writes, frictionloss_writes
from zmpkit.sim.world_fields import CandidateFields, FieldWrite

__all__ = ["SERVO_FIELD_RULE"]


def _motor_writes(
    model: mujoco.MjModel, joints: tuple[str, ...], doc: Mapping[str, Any], inductance: bool, n: int
) -> list[FieldWrite]:
    spec, pid, friction = doc["motor"], doc["pid"], doc["friction"]
    resistance = item(spec["resistance"])
    controller = dcmotor_controller(
        item(pid["kp"]),
        item(pid["ki"]),
        item(pid["kd"]),
        float(spec["gear_ratio"]),
        float(spec["torque_constant"]),
        resistance,
        spec.get("drive", "current") == "voltage",
        float(pid["integral_limit_link"]),
        float(spec["supply_voltage"]),
    )
    gains = (column(controller[0], n), column(controller[1], n), column(controller[2], n))
    return [
        *dcmotor_writes(
            model,
            joints,
            gains=gains,
            resistance=column(resistance, n),
            inductance=column(spec["inductance"], n) if inductance else None,
            damping=column(friction.get("viscous_motor", 0.0), n),
        ),
        *frictionloss_writes(model, joints, column(friction["coulomb_link"], n)),
    ]


def _write(
    model: mujoco.MjModel, description: RobotDescription, doc: Mapping[str, Any], n: int
) -> CandidateFields:
    effects, joints = description.effects, description.driven_joints
    writes: list[FieldWrite] = []
    if effects.motor:
        writes += _motor_writes(model, joints, doc, effects.inductance, n)
    if effects.gear:
        writes += gear_doc_writes(model, joints, doc["gear"], n)
    if effects.flex:
        writes += flex_doc_writes(model, doc.get("flex") or (), n)
    return CandidateFields(tuple(writes))


SERVO_FIELD_RULE = FieldRule(
    paths=(
        "pid.k[pid]",
        "motor.resistance",
        "motor.inductance",
        "friction.viscous_motor",
        "friction.coulomb_link",
        "gear.stiffness",
        "gear.damping",
        "gear.backlash",
        "flex[[]*].stiffness[[]0]",
        "flex[[]*].damping",
    ),
    write=_write,
)
"""The :class:`~zmpkit.robots.field_rule.FieldRule` of a servo-truth robot (module docstring)."""
