"""The one way a robot's MJCF gets its effects: G, M and I joint by joint, then F.

Every robot calls these: a virtual robot built in code on the MJCF it builds, a robot
file's robot (``robot.yaml``) on the MJCF its model file gives
(:func:`~zmpkit.robots.servo_truth.apply_servo_effects`). Per driven joint the gear
compliance (G) comes first, then the DC motor and its drive (M, with the winding inductance
of I); a joint without M keeps the servo its robot gives it. The flexible-link joints (F)
come last, and the MJCF is written out. The element builders are in
:mod:`zmpkit.sim.builder`.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence

from zmpkit.sim.builder import add_flex_joint, add_gear_compliance, add_motor, find_element
from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.drive import InductanceParams, MotorParams
from zmpkit.sim.effect_set import EffectSet

__all__ = ["add_drive_effects", "mjcf_with_flex"]


def _remove_model_servo(root: ET.Element, joint: str) -> None:
    """Remove the model's own servo of ``joint``: its actuators, ``armature`` and ``damping``.

    The motor's rotor inertia ``J N²``, friction and drive replace them (its joint defaults
    included).
    """
    for section_el in root.findall("actuator"):
        for actuator in list(section_el):
            if actuator.get("joint") == joint:
                section_el.remove(actuator)
    element = find_element(root, "joint", joint)
    element.set("armature", "0")
    element.set("damping", "0")


def add_drive_effects(
    root: ET.Element,
    joint: str,
    on: EffectSet,
    motors: Mapping[str, MotorParams],
    inductances: Mapping[str, InductanceParams],
    gear: GearParams | None,
    replaces_model_servo: bool = False,
) -> bool:
    """Apply the switched-on drive effects G, M and I to one driven ``joint`` of ``root``.

    Args:
        root: the MJCF being built (changed in place).
        joint: the driven joint.
        on: the switched-on effects.
        motors: joint → its motor, gear ratio and joint-side PID (effect M; read with M on).
        inductances: joint → its winding inductance (effect I; read with M and I on).
        gear: its gear compliance and backlash (effect G); None: the joint stays rigid
            between motor and link whatever G says.
        replaces_model_servo: the model already drives the joint (a robot file's ideal
            servo, its own ``armature`` and ``damping``): with M they are removed first.

    Returns:
        Whether the motor drives the joint (M on); if not, the caller gives it its servo.
    """
    if on.gear and gear is not None:
        add_gear_compliance(root, joint, gear)
    if not on.motor:
        return False
    if replaces_model_servo:
        _remove_model_servo(root, joint)
    add_motor(root, joint, motors[joint], inductances[joint] if on.inductance else None)
    return True


def mjcf_with_flex(root: ET.Element, on: EffectSet, flex: Sequence[FlexJoint]) -> str:
    """The MJCF text of ``root``, with the flexible-link joints ``flex`` added when F is on."""
    if on.flex:
        for joint in flex:
            add_flex_joint(root, joint)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")
