r"""The truth parameters of the virtual NAO's effects, read from a YAML file.

The shipped file is ``robots/nao/data/truth.yaml``. Pipelines never read the truth (a real
user cannot); the simulator and tests do. Every problem is reported as
:class:`~zmpkit.errors.InputFileError` naming the file and the field.

NAO's motor boards run a PID on the joint angle whose output is a *voltage* (MoToFlex,
paper B §II), scaled by NAO's stiffness factor ``s``. With the motor's torque constant K,
resistance R and gear ratio N, a voltage gain ``g`` [V/rad] is the joint-side torque gain

.. math:: k_{link} = s\,g\,K N / R \quad [N·m/rad],

and the drive's voltage clamp is the supply ``V_supply``. The simulated drive compensates the
back-EMF (:class:`~zmpkit.sim.drive.MotorParams`); ``friction.back_emf_damping: true`` adds it
back as a rotor damping ``K²/R`` [N·m·s/rad] (a voltage-mode drive; the link sees ``N² K²/R``),
which below the clamp is exact and at the clamp counts the back-EMF twice.

CAD vs real mass (effect ``C``): the ``torso`` section holds the real torso link's mass [kg]
and CoM [m, torso frame: x forward, y left, z up], which differ from the URDF's (the design
the IK and the walking pattern use). Its inertia at the CoM is the URDF's scaled by the mass
ratio (:meth:`NaoTruth.torso_inertial`). Unlike M, I, G, F, S it cannot be switched off: it is
what the real robot weighs.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from zmpkit.errors import InputFileError
from zmpkit.robots.nao.geometry import TORSO, Inertial
from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.drive import IdealServoParams, InductanceParams, MotorParams
from zmpkit.sim.sensor_errors import SensorParams
from zmpkit.sim.truth_file import TruthReader, flex_joint, section

__all__ = [
    "DEFAULT_TRUTH_PATH",
    "NaoTruth",
    "link_gains",
    "load_truth",
    "torso_inertia",
    "truth_from_doc",
]

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
        torso_mass_kg: the real torso link's mass [kg] (URDF/CAD: 1.04956).
        torso_com_m: its CoM in the torso frame (x forward, y left, z up) [m].
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
    torso_mass_kg: float
    torso_com_m: tuple[float, float, float]
    source: str = str(DEFAULT_TRUTH_PATH)

    def torso_inertial(self) -> Inertial:
        """The real torso link: mass [kg], CoM [m] and inertia [kg·m²].

        The inertia is the URDF's scaled by the mass ratio (same shape, denser).
        """
        return Inertial(self.torso_mass_kg, self.torso_com_m, torso_inertia(self.torso_mass_kg))


def torso_inertia(mass_kg: Any) -> tuple[Any, Any, Any]:
    """The real torso's (Ixx, Iyy, Izz) at its CoM: the URDF's times the mass ratio [kg·m²].

    ``mass_kg`` may be a numpy array (a fit's candidates): the same arithmetic, elementwise.
    """
    scale = mass_kg / TORSO.mass
    ixx, iyy, izz = TORSO.inertia
    return (scale * ixx, scale * iyy, scale * izz)


def link_gains(
    stiffness: Any, torque_constant: float, ratio: Any, resistance: float, pid: Mapping[str, Any]
) -> tuple[Any, Any, Any]:
    """The joint-side PID gains (kp, ki, kd) of the voltage gains ``pid`` (module docstring).

    ``k_link = s g K N / R`` [N·m/rad, N·m/(rad·s), N·m·s/rad]. The stiffness factor, the
    ratio and the gains may be numpy arrays (a fit's candidates, :mod:`.fit_fields`): the
    arithmetic is the same, element by element.
    """
    volts_to_torque = stiffness * torque_constant * ratio / resistance  # [N·m/V] at the joint
    return (
        volts_to_torque * _number(pid["p"]),
        volts_to_torque * _number(pid["i"]),
        volts_to_torque * _number(pid["d"]),
    )


def _number(value: Any) -> Any:
    """A truth number as a float, or a candidates' column (a numpy array) as it is."""
    return value if hasattr(value, "shape") else float(value)


def _motor(ratio: float, doc: Mapping[str, Any], path: Path) -> MotorParams:
    """One drive: the voltage PID turned into joint-side torque gains (module docstring)."""
    spec, pid = section(doc, "motor", path), section(doc, "pid_volts", path)
    friction, s = section(doc, "friction", path), float(section(doc, "stiffness", path))
    k, r = float(spec["torque_constant"]), float(spec["resistance"])
    kp, ki, kd = link_gains(s, k, float(ratio), r, pid)
    return MotorParams(
        torque_constant=k,
        resistance=r,
        voltage_limit=float(spec["supply_voltage"]),
        gear_ratio=float(ratio),
        rotor_inertia=float(spec["rotor_inertia"]),
        coulomb_friction_link=float(friction["coulomb_link"]),
        viscous_friction_motor=k * k / r if friction["back_emf_damping"] else 0.0,
        kp_link=kp,
        ki_link=ki,
        kd_link=kd,
        integral_limit_link=float(pid["integral_limit_link"]),
        servo_rate_hz=float(doc["servo_rate_hz"]),
    )


def _torso(doc: Mapping[str, Any], path: Path) -> tuple[float, tuple[float, float, float]]:
    """The ``torso`` section: (mass [kg], CoM [m]), checked (module docstring)."""
    torso = section(doc, "torso", path)
    if not isinstance(torso, Mapping):
        raise InputFileError(
            path, f"torso: expected a mapping with mass_kg and com_m, got {torso!r}", column="torso"
        )
    expected = {"mass_kg": "the real torso mass [kg]", "com_m": "its CoM [x, y, z] [m]"}
    for key, meaning in expected.items():
        if key not in torso:
            raise InputFileError(path, f"torso: missing '{key}' ({meaning})", column="torso")
    mass = torso["mass_kg"]
    if not _is_number(mass) or not math.isfinite(mass) or mass <= 0.0:
        raise InputFileError(
            path, f"torso.mass_kg must be a mass > 0 kg, got {mass!r}", column="torso"
        )
    com = torso["com_m"]
    if (
        not isinstance(com, list | tuple)
        or len(com) != 3
        or not all(_is_number(v) and math.isfinite(v) for v in com)
    ):
        raise InputFileError(
            path,
            f"torso.com_m must be 3 finite numbers [x, y, z] in the torso frame [m], got {com!r}",
            column="torso",
        )
    return float(mass), (float(com[0]), float(com[1]), float(com[2]))


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _parse(doc: Mapping[str, Any], path: Path) -> NaoTruth:
    joints = section(doc, "joints", path)
    inductance = InductanceParams(float(section(doc, "motor", path)["inductance"]))
    sensors = dict(section(doc, "sensors", path))
    offsets = {side: tuple(float(v) for v in vec) for side, vec in sensors.pop("ft_offset").items()}
    torso_mass, torso_com = _torso(doc, path)
    return NaoTruth(
        servo_rate_hz=float(section(doc, "servo_rate_hz", path)),
        motors={name: _motor(ratio, doc, path) for name, ratio in joints.items()},
        inductances=dict.fromkeys(joints, inductance),
        ideal_servo=IdealServoParams(**section(doc, "ideal_servo", path)),
        gear=GearParams(**section(doc, "gear", path)),
        flex=tuple(flex_joint(e) for e in section(doc, "flex", path)),
        floor_friction=float(section(doc, "contact", path)["friction"]),
        sensors=SensorParams(ft_offset=offsets["right"], **sensors),
        ft_offsets=offsets,
        torso_mass_kg=torso_mass,
        torso_com_m=torso_com,
        source=str(path),
    )


_READER = TruthReader(DEFAULT_TRUTH_PATH, _parse)
load_truth = _READER.load
"""Read a truth file of the virtual NAO (:meth:`~zmpkit.sim.truth_file.TruthReader.load`)."""
truth_from_doc = _READER.from_doc
"""The truth of a document in memory (:meth:`~zmpkit.sim.truth_file.TruthReader.from_doc`)."""
