"""The truth parameters of the virtual TEO's effects, read from a YAML file.

The shipped file is ``robots/teo/data/truth.yaml``; a user's ``--truth FILE`` with the same
layout replaces it. Pipelines never read the truth (a real user cannot); the simulator and
tests do. Every problem is reported as :class:`~zmpkit.errors.InputFileError` naming the
file and the field.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from zmpkit.errors import InputFileError, ZmpkitError
from zmpkit.sim.effects import (
    FlexJoint,
    GearParams,
    InductanceParams,
    MotorParams,
    SensorParams,
)

__all__ = ["DEFAULT_TRUTH_PATH", "TeoTruth", "load_truth"]

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


def _section(doc: Mapping[str, Any], key: str, path: Path) -> Any:
    if key not in doc:
        raise InputFileError(path, f"missing section '{key}'", column=key)
    return doc[key]


def _motor(name: str, entry: Mapping[str, Any], doc: Mapping[str, Any], path: Path) -> MotorParams:
    types = _section(doc, "motor_types", path)
    kind = entry.get("motor")
    if kind not in types:
        raise InputFileError(
            path, f"joint {name}: unknown motor {kind!r}; known: {sorted(types)}", column="joints"
        )
    spec = types[kind]
    pid, friction = _section(doc, "pid", path), _section(doc, "friction", path)
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


def _flex(entry: Mapping[str, Any]) -> FlexJoint:
    return FlexJoint(
        name=entry["name"],
        body=entry["body"],
        axis=tuple(float(a) for a in entry["axis"]),  # type: ignore[arg-type]
        anchor=tuple(float(a) for a in entry.get("anchor", (0, 0, 0))),  # type: ignore[arg-type]
        stiffness=tuple(float(k) for k in entry["stiffness"]),  # type: ignore[arg-type]
        damping=float(entry.get("damping", 0.0)),
        softening_torque=float(entry.get("softening_torque", 0.0)),
        softening_torque_range=float(entry.get("softening_torque_range", 50.0)),
        softening_stages=int(entry.get("softening_stages", 6)),
    )


def _parse(doc: Mapping[str, Any], path: Path) -> TeoTruth:
    joints = _section(doc, "joints", path)
    motors = {name: _motor(name, entry, doc, path) for name, entry in joints.items()}
    types = doc["motor_types"]
    inductances = {
        name: InductanceParams(types[entry["motor"]]["inductance"])
        for name, entry in joints.items()
    }
    sensors = dict(_section(doc, "sensors", path))
    offsets = {side: tuple(float(v) for v in vec) for side, vec in sensors.pop("ft_offset").items()}
    payload = _section(doc, "payload", path)
    gear = dict(_section(doc, "gear", path))
    gear_joints = tuple(gear.pop("joints", joints))
    unknown = sorted(set(gear_joints) - set(joints))
    if unknown:
        raise InputFileError(
            path, f"gear.joints: unknown joints {unknown}; known: {sorted(joints)}", column="gear"
        )
    return TeoTruth(
        servo_rate_hz=float(_section(doc, "servo_rate_hz", path)),
        motors=motors,
        inductances=inductances,
        gear=GearParams(**gear),
        gear_joints=gear_joints,
        flex=tuple(_flex(e) for e in _section(doc, "flex", path)),
        sensors=SensorParams(ft_offset=offsets["right"], **sensors),
        ft_offsets=offsets,
        payload_mass_kg=float(payload["mass_kg"]),
        payload_position_m=tuple(float(v) for v in payload["position_m"]),  # type: ignore[arg-type]
        source=str(path),
    )


def load_truth(path: str | Path | None = None) -> TeoTruth:
    """Read the truth parameters of the virtual TEO.

    Args:
        path: a YAML file with the layout of the shipped one; ``None`` = the shipped truth.

    Raises:
        InputFileError: if the file cannot be read or a field is missing or invalid.
    """
    file = Path(path) if path is not None else DEFAULT_TRUTH_PATH
    try:
        doc = yaml.safe_load(file.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as exc:
        raise InputFileError(file, f"cannot read the truth file: {exc}") from None
    if not isinstance(doc, Mapping):
        raise InputFileError(file, "expected a mapping of sections at the top level")
    try:
        return _parse(doc, file)
    except InputFileError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError, ZmpkitError) as exc:
        raise InputFileError(file, f"invalid truth: {exc}") from None
