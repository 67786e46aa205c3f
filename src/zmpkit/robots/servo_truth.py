r"""The truth of a robot-file robot with servo values: motors, gears, flexible links, sensors.

A built-in robot described by a ``robot.yaml`` (the OP3) ships a truth YAML with this layout;
its effects M, I, G, F are then applied to the MJCF the robot file builds
(:func:`apply_servo_effects`), the same native mechanisms as NAO's and TEO's
(:mod:`zmpkit.sim.builder`). Layout (SI units)::

    servo_rate_hz: 1000.0                 # drive loop = physics rate [Hz]
    motor:                                # every leg joint's motor
      gear_ratio: 353.5                   # N [-]
      torque_constant: 0.00705            # K [N·m/A] = back-EMF constant [V·s/rad]
      resistance: 7.29                    # R [Ω]
      supply_voltage: 12.0                # voltage clamp [V]
      inductance: 1.0e-4                  # L [H] (effect I)
      rotor_inertia: 3.6e-7               # J [kg·m²]; the link sees J N²
      drive: voltage                      # optional: current (default) or voltage
    pid: {kp: 60.0, ki: 60.0, kd: 0.3, integral_limit_link: 0.05}  # joint side
    friction: {coulomb_link: 0.03}        # [N·m] at the joint
    ideal_servo: {kp: ..., ki: ..., kd: ...}  # optional: joints with the motor effect off
    gear: {stiffness: .., damping: .., backlash: .., inertia_link: ..}
    flex: [{name: .., body: .., axis: [..], anchor: [..], stiffness: [k1, k2, k3], damping: ..}]
    sensors: {...}                        # optional: SensorParams fields; default scaled

The drive's PID gains are joint-side torque gains (:class:`~zmpkit.sim.drive.MotorParams`):
at stall the joint torque saturates at :math:`N K V / R`. ``drive`` says what the PID
commands: ``current`` (a current loop that compensates the back-EMF) or ``voltage`` (a PWM
drive: the PID's output is the winding voltage, so the back-EMF damps the joint by
:math:`N^2 K^2 / R` and the speed-torque line bounds it at the clamp). A voltage drive's
gains are those at standstill (volts per rad times :math:`N K / R`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from zmpkit.errors import InputFileError
from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.drive import IdealServoParams, InductanceParams, MotorParams
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.joint_effects import add_drive_effects, mjcf_with_flex
from zmpkit.sim.sensor_errors import SensorParams
from zmpkit.sim.truth_file import flex_joint, parse_truth_doc, read_truth_file, section

__all__ = [
    "DRIVES",
    "ServoTruth",
    "apply_servo_effects",
    "read_servo_truth",
    "servo_truth_from_doc",
]


@dataclass(frozen=True)
class ServoTruth:
    """The hidden parameters of a robot-file robot with servo values.

    Attributes:
        motor: every leg joint's motor, gear ratio and joint-side PID.
        inductance: winding inductance (effect I).
        ideal_servo: the stiff servo of a joint whose motor effect is off; None: the robot
            file's (derived from its weight).
        gear: gear compliance and backlash, the same for every leg joint (effect G).
        flex: flexible-link joints (effect F).
        sensors: sensor errors (effect S); None: the defaults scaled by the robot's weight.
        source: the file it came from.
    """

    motor: MotorParams
    inductance: InductanceParams
    ideal_servo: IdealServoParams | None
    gear: GearParams
    flex: tuple[FlexJoint, ...]
    sensors: SensorParams | None
    source: str = ""


DRIVES = ("current", "voltage")
"""What a drive's PID commands (module docstring)."""


def _motor(doc: Mapping[str, Any], path: Path) -> MotorParams:
    spec, pid = section(doc, "motor", path), section(doc, "pid", path)
    friction = section(doc, "friction", path)
    drive = spec.get("drive", "current")
    if drive not in DRIVES:
        raise InputFileError(
            path, f"motor.drive: expected one of {', '.join(DRIVES)}, got {drive!r}", column="motor"
        )
    return MotorParams(
        torque_constant=float(spec["torque_constant"]),
        resistance=float(spec["resistance"]),
        voltage_limit=float(spec["supply_voltage"]),
        gear_ratio=float(spec["gear_ratio"]),
        rotor_inertia=float(spec["rotor_inertia"]),
        coulomb_friction_link=float(friction["coulomb_link"]),
        viscous_friction_motor=float(friction.get("viscous_motor", 0.0)),
        kp_link=float(pid["kp"]),
        ki_link=float(pid["ki"]),
        kd_link=float(pid["kd"]),
        integral_limit_link=float(pid["integral_limit_link"]),
        servo_rate_hz=float(section(doc, "servo_rate_hz", path)),
        voltage_drive=drive == "voltage",
    )


def _tuples(values: Mapping[str, Any]) -> dict[str, Any]:
    return {
        k: tuple(float(x) for x in v) if isinstance(v, Sequence) else float(v)
        for k, v in values.items()
    }


def _parse(doc: Mapping[str, Any], path: Path) -> ServoTruth:
    ideal = doc.get("ideal_servo")
    sensors = doc.get("sensors")
    if sensors is not None and not isinstance(sensors, Mapping):
        raise InputFileError(
            path, f"sensors: expected a mapping, got {sensors!r}", column="sensors"
        )
    return ServoTruth(
        motor=_motor(doc, path),
        inductance=InductanceParams(float(section(doc, "motor", path)["inductance"])),
        ideal_servo=None if ideal is None else IdealServoParams(**ideal),
        gear=GearParams(**section(doc, "gear", path)),
        flex=tuple(flex_joint(e) for e in doc.get("flex") or ()),
        sensors=None if sensors is None else SensorParams(**_tuples(sensors)),
        source=str(path),
    )


def read_servo_truth(path: str | Path) -> ServoTruth:
    """Read a servo truth YAML (module docstring).

    Raises:
        InputFileError: naming the file and the field that is missing or invalid.
    """
    return read_truth_file(Path(path), _parse)


def servo_truth_from_doc(doc: Mapping[str, Any], source: str | Path = "<truth>") -> ServoTruth:
    """The servo truth of a YAML document already in memory.

    Raises:
        InputFileError: naming ``source`` if a field is missing or invalid.
    """
    return parse_truth_doc(doc, Path(source), _parse)


def apply_servo_effects(
    mjcf: str, joints: Sequence[str], effects: EffectSet, truth: ServoTruth
) -> str:
    """``mjcf`` (ideal servos on ``joints``) with the effects M, I, G, F of ``truth`` applied.

    M replaces each joint's ideal servo by the DC motor and its PID drive (I adds the winding
    inductance), and the model's own servo dynamics on that joint (its ``armature``,
    ``damping`` and ``frictionloss``, e.g. a Menagerie model's system-identified values) by
    the motor's rotor inertia, friction and drive; G splits each joint into motor side and
    gear deflection with backlash; F adds the flexible-link joints.
    """
    root = ET.fromstring(mjcf)
    motors = dict.fromkeys(joints, truth.motor)
    inductances = dict.fromkeys(joints, truth.inductance)
    for joint in joints:
        add_drive_effects(root, joint, effects, motors, inductances, truth.gear, True)
    return mjcf_with_flex(root, effects, truth.flex)
