"""The truth parameters of the virtual TEO's effects, read from a YAML file.

The shipped file is ``robots/teo/data/truth.yaml``; a user's ``--truth FILE`` with the same
layout replaces it. Pipelines never read the truth (a real user cannot); the simulator and
tests do. Every problem is reported as :class:`~zmpkit.errors.InputFileError` naming the
file and the field.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from zmpkit.errors import InputFileError
from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.drive import InductanceParams, MotorParams
from zmpkit.sim.sensor_errors import SensorParams, TrialVariability
from zmpkit.sim.truth_file import TruthReader, flex_joint, section, vector3

__all__ = ["DEFAULT_TRUTH_PATH", "TeoTruth", "load_truth", "truth_from_doc"]

DEFAULT_TRUTH_PATH = Path(__file__).with_name("data") / "truth.yaml"
"""The truth shipped with zmpkit."""


@dataclass(frozen=True)
class TeoTruth:
    """All hidden parameters of the virtual TEO.

    Attributes:
        servo_rate_hz: drive control rate = physics rate [Hz].
        motors: driven joint name → motor, gear and PID parameters.
        inductances: driven joint name → winding inductance.
        gear: gear compliance and backlash, the same for every geared joint.
        gear_joints: the driven joints that get gear compliance (G); the others stay
            rigid between motor and link (a gear DOF costs simulation time).
        flex: passive structural compliances.
        sensors: sensor errors (the F-T offset field is the right foot's).
        ft_offsets: foot side → F-T offset (Fx, Fy, Fz, Tx, Ty, Tz) [N, N·m].
        payload_mass_kg: point mass reconciling the manual with the paper [kg].
        payload_position_m: its position in the trunk (frontal waist) frame [m].
        source: the file it came from.
        ft_gain_errors: foot side → relative gain error per axis [-], when the file gives
            ``sensors.ft_gain_error`` per sensor (``{right: [6], left: [6]}``); empty when
            it gives one number for all.
        variability: the optional ``variability`` section (trial-to-trial differences).
    """

    servo_rate_hz: float
    motors: Mapping[str, MotorParams]
    inductances: Mapping[str, InductanceParams]
    gear: GearParams
    gear_joints: tuple[str, ...]
    flex: tuple[FlexJoint, ...]
    sensors: SensorParams
    ft_offsets: Mapping[str, tuple[float, ...]]
    payload_mass_kg: float
    payload_position_m: tuple[float, float, float]
    source: str = str(DEFAULT_TRUTH_PATH)
    ft_gain_errors: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    variability: TrialVariability = field(default_factory=TrialVariability)


def _motor(name: str, entry: Mapping[str, Any], doc: Mapping[str, Any], path: Path) -> MotorParams:
    types = section(doc, "motor_types", path)
    kind = entry.get("motor")
    if kind not in types:
        raise InputFileError(
            path, f"joint {name}: unknown motor {kind!r}; known: {sorted(types)}", column="joints"
        )
    spec = types[kind]
    pid, friction = section(doc, "pid", path), section(doc, "friction", path)
    return MotorParams(
        torque_constant=spec["torque_constant"],
        resistance=spec["resistance"],
        voltage_limit=spec["voltage_limit"],
        gear_ratio=entry["gear_ratio"],
        rotor_inertia=spec["rotor_inertia"],
        coulomb_friction_link=friction["coulomb_link"],
        viscous_friction_motor=friction["viscous_motor"],
        kp_link=pid["kp_link"],
        ki_link=pid["ki_link"],
        kd_link=pid["kd_link"],
        integral_limit_link=pid["integral_limit_link"],
        servo_rate_hz=doc["servo_rate_hz"],
    )


def _parse(doc: Mapping[str, Any], path: Path) -> TeoTruth:
    joints = section(doc, "joints", path)
    motors = {name: _motor(name, entry, doc, path) for name, entry in joints.items()}
    types = doc["motor_types"]
    inductances = {
        name: InductanceParams(types[entry["motor"]]["inductance"])
        for name, entry in joints.items()
    }
    sensors = dict(section(doc, "sensors", path))
    offsets = {side: tuple(float(v) for v in vec) for side, vec in sensors.pop("ft_offset").items()}
    gains = sensors.pop("ft_gain_error", 0.0)
    per_sensor = isinstance(gains, Mapping)
    if per_sensor:
        gains = {side: tuple(float(v) for v in vec) for side, vec in gains.items()}
        if sorted(gains) != ["left", "right"] or any(len(g) != 6 for g in gains.values()):
            raise ValueError(
                "sensors.ft_gain_error per sensor must be {right: [6 values], left: [6 values]}"
            )
    payload = section(doc, "payload", path)
    gear = dict(section(doc, "gear", path))
    gear_joints = tuple(gear.pop("joints", joints))
    unknown = sorted(set(gear_joints) - set(joints))
    if unknown:
        raise InputFileError(
            path, f"gear.joints: unknown joints {unknown}; known: {sorted(joints)}", column="gear"
        )
    return TeoTruth(
        servo_rate_hz=float(section(doc, "servo_rate_hz", path)),
        motors=motors,
        inductances=inductances,
        gear=GearParams(**gear),
        gear_joints=gear_joints,
        flex=tuple(flex_joint(e) for e in section(doc, "flex", path)),
        sensors=SensorParams(
            ft_offset=offsets["right"],
            ft_gain_error=float(gains["right"][0]) if per_sensor else float(gains),
            **sensors,
        ),
        ft_offsets=offsets,
        ft_gain_errors=gains if per_sensor else {},
        variability=TrialVariability(**doc.get("variability", {})),
        payload_mass_kg=float(payload["mass_kg"]),
        payload_position_m=vector3(payload["position_m"]),
        source=str(path),
    )


_READER = TruthReader(DEFAULT_TRUTH_PATH, _parse)
load_truth = _READER.load
"""Read a truth file of the virtual TEO (:meth:`~zmpkit.sim.truth_file.TruthReader.load`)."""
truth_from_doc = _READER.from_doc
"""The truth of a document in memory (:meth:`~zmpkit.sim.truth_file.TruthReader.from_doc`)."""
