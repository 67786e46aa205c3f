"""Apply the switched-on effects to a robot's MJCF, using MuJoCo-native mechanisms only.

Every effect that changes the physics becomes model elements, so the simulation runs at C
speed and stays usable with ``mujoco.rollout`` (and later MJX):

- **M** → a ``dcmotor`` actuator per driven joint: torque constant, resistance, back-EMF,
  gear ratio as the actuator ``gear``, rotor inertia as actuator ``armature`` (reflected as
  J N²), viscous friction as actuator ``damping`` (reflected as b N²), Coulomb friction as
  joint ``frictionloss``, and the drive's PID with its voltage clamp as the on-board
  ``controller`` (input ``pos``; a voltage drive's back-EMF left uncompensated, see
  :func:`add_motor`). The controller runs every physics step, so the world's timestep is
  the drive's servo period.
- **I** → the ``dcmotor`` ``inductance`` (one activation state for the current).
- **G** → a second, passive hinge on the same axis in the same body (the body turns by the
  sum of both angles: motor side + gear deflection) and a fixed tendon on the deflection
  whose spring has a dead band ``springlength = [-b/2, b/2]`` (backlash) and the gear's
  stiffness and damping. The motor-side joint carries the gear-train inertia.
- **F** → passive hinges with MuJoCo's polynomial joint spring and damping, or with a
  softening spring (:mod:`zmpkit.sim.spring`): the joint's linear spring plus one fixed
  tendon per further segment, whose dead-band spring of negative stiffness lowers the
  tangent stiffness past its breakpoint.
- Without **M** the joint is driven by a stiff native ``pid`` actuator ("ideal joint").

The **S** effects act on the readings and live in :mod:`zmpkit.sim.sensing`.

Actuator controls are position setpoints in actuator length: ``ctrl = gear * q_ref`` [rad
at the motor for ``dcmotor``; rad at the joint for ``pid``].
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError
from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.drive import IdealServoParams, InductanceParams, MotorParams
from zmpkit.sim.spring import SofteningSpring

__all__ = [
    "GEAR_JOINT_SUFFIX",
    "add_flex_joint",
    "add_gear_compliance",
    "add_ideal_servo",
    "add_motor",
    "dcmotor_controller",
    "find_element",
]

Number: TypeAlias = float | NDArray[np.float64]
"""A float, or an array of them (one per candidate)."""

GEAR_JOINT_SUFFIX = "_gear"
"""Name suffix of the passive gear-deflection joint that **G** adds next to a driven joint."""


def _fmt(*values: float) -> str:
    return " ".join(f"{v:.10g}" for v in values)


def find_element(root: ET.Element, tag: str, name: str) -> ET.Element:
    """Return the unique element ``<tag name=name>`` under ``root``.

    Raises:
        ModelError: if there is none, listing the names that exist.
    """
    found = [el for el in root.iter(tag) if el.get("name") == name]
    if len(found) != 1:
        names = sorted(el.get("name", "?") for el in root.iter(tag))
        raise ModelError(f"MJCF has {len(found)} <{tag}> named {name!r}; known: {names}")
    return found[0]


def _actuator_section(root: ET.Element) -> ET.Element:
    section = root.find("actuator")
    return section if section is not None else ET.SubElement(root, "actuator")


def add_motor(
    root: ET.Element,
    joint: str,
    motor: MotorParams,
    inductance: InductanceParams | None = None,
) -> ET.Element:
    """Drive ``joint`` with a DC motor, gear and PID drive (effects M and, optionally, I).

    The joint-side PID gains become motor-side gains ``k / N²`` (torque at the rotor per
    rad at the rotor); the integral clamp becomes ``N * integral_limit_link``. MuJoCo's
    ``dcmotor`` controller is a current drive: its voltage is ``(R/K) tau + K omega`` (the
    back-EMF compensated) with its derivative term on the measured rotor speed only. A
    voltage drive (``motor.voltage_drive``) adds ``K²/R`` to that derivative gain, which
    cancels the compensation exactly: the voltage is then ``(R/K)`` times the PID's torque
    command, clamped, at every speed.

    Returns:
        The new ``<dcmotor>`` element, named after the joint.
    """
    jel = find_element(root, "joint", joint)
    jel.set("frictionloss", _fmt(motor.coulomb_friction_link))
    controller = dcmotor_controller(
        motor.kp_link,
        motor.ki_link,
        motor.kd_link,
        motor.gear_ratio,
        motor.torque_constant,
        motor.resistance,
        motor.voltage_drive,
        motor.integral_limit_link,
        motor.voltage_limit,
    )
    attrs = {
        "name": joint,
        "joint": joint,
        "gear": _fmt(motor.gear_ratio),
        "armature": _fmt(motor.rotor_inertia),
        "damping": _fmt(motor.viscous_friction_motor),
        "resistance": _fmt(motor.resistance),
        "motorconst": _fmt(motor.torque_constant, motor.torque_constant),
        "input": "pos",
        "controller": _fmt(*(float(v) for v in controller)),
    }
    if inductance is not None:
        attrs["inductance"] = _fmt(inductance.inductance, 0.0)
    return ET.SubElement(_actuator_section(root), "dcmotor", attrs)


def dcmotor_controller(
    kp_link: Number,
    ki_link: Number,
    kd_link: Number,
    gear_ratio: float,
    torque_constant: float,
    resistance: Number,
    voltage_drive: bool,
    integral_limit_link: float,
    voltage_limit: float,
) -> tuple[Number, Number, Number, float, float, float]:
    """The ``controller`` attribute of :func:`add_motor`'s ``dcmotor``: (kp, ki, kd, 0, imax, V).

    Motor-side gains ``k_link / N²`` [N·m/rad at the rotor, ...], the voltage drive's
    ``K²/R`` added to kd, the integral clamp ``N * integral_limit_link`` [rad·s at the
    rotor] and the voltage clamp [V]. The gains and the resistance may be numpy arrays (one
    value per candidate): the arithmetic is the same, element by element
    (:mod:`zmpkit.sim.effect_fields` writes them into compiled models).
    """
    n2 = gear_ratio**2
    back_emf = torque_constant**2 / resistance  # [N·m·s/rad] at the rotor
    return (
        kp_link / n2,
        ki_link / n2,
        kd_link / n2 + (back_emf if voltage_drive else 0.0),
        0.0,
        integral_limit_link * gear_ratio,
        voltage_limit,
    )


def add_ideal_servo(root: ET.Element, joint: str, servo: IdealServoParams) -> ET.Element:
    """Drive ``joint`` with a stiff PID and no torque limit (the motor effect off)."""
    find_element(root, "joint", joint)
    attrs = {
        "name": joint,
        "joint": joint,
        "kp": _fmt(servo.kp),
        "kv": _fmt(servo.kd),
        "input": "pos",
    }
    if servo.ki > 0.0:
        attrs["ki"] = _fmt(servo.ki)
    return ET.SubElement(_actuator_section(root), "pid", attrs)


def _parent_of(root: ET.Element, child: ET.Element) -> ET.Element:
    for parent in root.iter():
        if child in list(parent):
            return parent
    raise ModelError(f"element {child.get('name')!r} has no parent")  # pragma: no cover


def add_gear_compliance(root: ET.Element, joint: str, gear: GearParams) -> str:
    """Split ``joint`` into motor side + gear deflection with backlash (effect G).

    Adds a hinge ``joint + GEAR_JOINT_SUFFIX`` right after ``joint`` in the same body (same
    anchor and axis) and a fixed tendon on it whose dead-band spring is the gear. The link
    angle is then ``q[joint] + q[joint_gear]``; ``q[joint]`` is the motor side, where the
    encoder sits.

    Returns:
        The name of the deflection joint.
    """
    jel = find_element(root, "joint", joint)
    armature = float(jel.get("armature", "0")) + gear.inertia_link
    jel.set("armature", _fmt(armature))
    body = _parent_of(root, jel)
    name = joint + GEAR_JOINT_SUFFIX
    # unlimited whatever the model's joint defaults say (Menagerie's Apollo gives every joint
    # a range its default class inherits; a deflection joint has none of its own)
    gel = ET.Element(
        "joint",
        {"name": name, "type": "hinge", "axis": jel.get("axis", "0 0 1"), "limited": "false"},
    )
    if jel.get("pos") is not None:
        gel.set("pos", jel.get("pos", ""))
    body.insert(list(body).index(jel) + 1, gel)
    tendons = root.find("tendon")
    if tendons is None:
        tendons = ET.SubElement(root, "tendon")
    half = 0.5 * gear.backlash
    tendon = ET.SubElement(
        tendons,
        "fixed",
        {
            "name": name,
            "springlength": _fmt(-half, half),
            "stiffness": _fmt(gear.stiffness),
            "damping": _fmt(gear.damping),
        },
    )
    ET.SubElement(tendon, "joint", {"joint": name, "coef": "1"})
    return name


def add_flex_joint(root: ET.Element, flex: FlexJoint) -> ET.Element:
    """Add a passive compliant hinge to ``flex.body`` (effect F).

    The hinge goes after the body's existing joints, so it deflects the body (and what it
    carries) relative to the driven joints. A softening spring adds the tendons
    ``{flex.name}_stage{j}``, j = 1 … n − 1.
    """
    body = find_element(root, "body", flex.body)
    spring = flex.spring
    stiffness = flex.stiffness if spring is None else (spring.segment_stiffness[0], 0.0, 0.0)
    attrs = {
        "name": flex.name,
        "type": "hinge",
        "axis": _fmt(*flex.axis),
        "pos": _fmt(*flex.anchor),
        "stiffness": _fmt(*stiffness),
        "damping": _fmt(flex.damping),
        "limited": "false",
    }
    joints = [i for i, el in enumerate(body) if el.tag == "joint"]
    where = joints[-1] + 1 if joints else 0
    el = ET.Element("joint", attrs)
    body.insert(where, el)
    if spring is not None:
        _add_softening_stages(root, flex.name, spring)
    return el


def _add_softening_stages(root: ET.Element, joint: str, spring: SofteningSpring) -> None:
    tendons = root.find("tendon")
    if tendons is None:
        tendons = ET.SubElement(root, "tendon")
    k = spring.segment_stiffness
    for j in range(1, spring.stages):
        edge = spring.breakpoints[j]
        tendon = ET.SubElement(
            tendons,
            "fixed",
            {
                "name": f"{joint}_stage{j}",
                "springlength": _fmt(-edge, edge),
                "stiffness": _fmt(k[j] - k[j - 1]),
            },
        )
        ET.SubElement(tendon, "joint", {"joint": joint, "coef": "1"})
