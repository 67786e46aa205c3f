"""The truth parameters of the virtual NAO's effects, read from a YAML file.

The shipped file is ``robots/nao/data/truth.yaml``. Pipelines never read the truth (a real
user cannot); the simulator and tests do. Every problem is reported as
:class:`~zmpkit.errors.InputFileError` naming the file and the field.

NAO's motor boards run a PID on the joint angle whose output is a *voltage* (MoToFlex,
paper B §II), scaled by NAO's stiffness factor ``s``. With the motor's torque constant K,
resistance R and gear ratio N, a voltage gain ``g`` [V/rad] is the joint-side torque gain

.. math:: k_{link} = s\\,g\\,K N / R \\quad [N·m/rad],

and the drive's voltage clamp is the supply ``V_supply``. The simulated drive compensates the
back-EMF (:class:`~zmpkit.sim.effects.MotorParams`); ``friction.back_emf_damping: true`` adds it
back as a rotor damping ``K²/R`` [N·m·s/rad] (a voltage-mode drive; the link sees ``N² K²/R``),
which below the clamp is exact and at the clamp counts the back-EMF twice.
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
    IdealServoParams,
    InductanceParams,
    MotorParams,
    SensorParams,
)

__all__ = ["DEFAULT_TRUTH_PATH", "NaoTruth", "load_truth"]

DEFAULT_TRUTH_PATH = Path(__file__).with_name("data") / "truth.yaml"
"""The truth shipped with zmpkit."""


@dataclass(frozen=True)
class NaoTruth:
    """All hidden parameters of the virtual NAO.

    Attributes:
        servo_rate_hz: motor-board control rate = physics rate [Hz].
        motors: driven joint name → motor, gear and PID parameters.
        inductances: driven joint name → winding inductance.
        ideal_servo: the stiff servo of a joint whose motor effect is off.
        gear: gear compliance and backlash, the same for every driven joint.
        flex: flexible-link joints.
        floor_friction: sole–floor sliding friction coefficient [-].
        sensors: sensor errors (the F-T offset field is the right foot's).
        ft_offsets: foot side → F-T offset (Fx, Fy, Fz, Tx, Ty, Tz) [N, N·m].
        source: the file it came from.
    """

    servo_rate_hz: float
    motors: Mapping[str, MotorParams]
    inductances: Mapping[str, InductanceParams]
    ideal_servo: IdealServoParams
    gear: GearParams
    flex: tuple[FlexJoint, ...]
    floor_friction: float
    sensors: SensorParams
    ft_offsets: Mapping[str, tuple[float, ...]]
    source: str = str(DEFAULT_TRUTH_PATH)


def _section(doc: Mapping[str, Any], key: str, path: Path) -> Any:
    if key not in doc:
        raise InputFileError(path, f"missing section '{key}'", column=key)
    return doc[key]


def _motor(ratio: float, doc: Mapping[str, Any], path: Path) -> MotorParams:
    """One drive: the voltage PID turned into joint-side torque gains (module docstring)."""
    spec, pid = _section(doc, "motor", path), _section(doc, "pid_volts", path)
    friction, s = _section(doc, "friction", path), float(_section(doc, "stiffness", path))
    k, r = float(spec["torque_constant"]), float(spec["resistance"])
    volts_to_torque = s * k * float(ratio) / r  # [N·m/V] at the joint
    return MotorParams(
        torque_constant=k,
        resistance=r,
        voltage_limit=float(spec["supply_voltage"]),
        gear_ratio=float(ratio),
        rotor_inertia=float(spec["rotor_inertia"]),
        coulomb_friction_link=float(friction["coulomb_link"]),
        viscous_friction_motor=k * k / r if friction["back_emf_damping"] else 0.0,
        kp_link=volts_to_torque * float(pid["p"]),
        ki_link=volts_to_torque * float(pid["i"]),
        kd_link=volts_to_torque * float(pid["d"]),
        integral_limit_link=float(pid["integral_limit_link"]),
        servo_rate_hz=float(doc["servo_rate_hz"]),
    )


def _flex(entry: Mapping[str, Any]) -> FlexJoint:
    return FlexJoint(
        name=entry["name"],
        body=entry["body"],
        axis=tuple(float(a) for a in entry["axis"]),  # type: ignore[arg-type]
        anchor=tuple(float(a) for a in entry.get("anchor", (0, 0, 0))),  # type: ignore[arg-type]
        stiffness=tuple(float(k) for k in entry["stiffness"]),  # type: ignore[arg-type]
        damping=float(entry.get("damping", 0.0)),
    )


def _parse(doc: Mapping[str, Any], path: Path) -> NaoTruth:
    joints = _section(doc, "joints", path)
    inductance = InductanceParams(float(_section(doc, "motor", path)["inductance"]))
    sensors = dict(_section(doc, "sensors", path))
    offsets = {side: tuple(float(v) for v in vec) for side, vec in sensors.pop("ft_offset").items()}
    return NaoTruth(
        servo_rate_hz=float(_section(doc, "servo_rate_hz", path)),
        motors={name: _motor(ratio, doc, path) for name, ratio in joints.items()},
        inductances=dict.fromkeys(joints, inductance),
        ideal_servo=IdealServoParams(**_section(doc, "ideal_servo", path)),
        gear=GearParams(**_section(doc, "gear", path)),
        flex=tuple(_flex(e) for e in _section(doc, "flex", path)),
        floor_friction=float(_section(doc, "contact", path)["friction"]),
        sensors=SensorParams(ft_offset=offsets["right"], **sensors),
        ft_offsets=offsets,
        source=str(path),
    )


def load_truth(path: str | Path | None = None) -> NaoTruth:
    """Read the truth parameters of the virtual NAO.

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
