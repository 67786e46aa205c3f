r"""``zmpkit robot truth init``: a first servo truth for a user's robot, every guess marked.

A robot file without a ``truth:`` has no motor, gear or link values: ``--effects all`` runs
its sensor errors only, and the simulator fit has nothing to fit. This writes a truth in the
layout of :mod:`zmpkit.robots.servo_truth` for the robot's leg joints (one motor model for
all of them, the layout's), taking from the model what it states, over the leg joints
(their median):

- the **position gain** ``kp`` and **damping** ``kd`` of a position actuator
  (``gainprm[0]``, ``−biasprm[2]``), unless that gain would let the robot sag more than
  :data:`MAX_SAG_RAD` under the moment of its weight, :math:`m g h_{CoM} / k_p` (a learned
  policy's gain or a soft factory setting, not a drive that follows a walk). Where the model
  states no gain, or one that soft, the template ASSUMES the stiffer of
  :math:`k_p = \tau_{stall} / 0.05` rad (the drive saturates at 0.05 rad of error) and
  :math:`k_p = m g h_{CoM} / 0.04` rad (the weight's moment held within
  :data:`HOLD_SAG_RAD`, as NAO's drive holds it), with :math:`k_d = 0.02\,k_p` s, and
  says beside it what the model stated;
- the **stall torque** from the actuator's ``forcerange`` or the joint's
  ``actuatorfrcrange`` (a URDF's ``<limit effort>``), else
  :math:`\tau_{stall} = \tfrac12 m g h_{hip}` (ASSUMED: holds the robot on one bent leg);
- the **armature** (:math:`J N^2`, the rotor inertia seen at the joint) and the joint's
  **Coulomb friction** (``frictionloss``).

Everything else is ASSUMED and marked so in the file: gear ratio :math:`N = 200`, supply
12 V, no-load joint speed :math:`\omega_{nl} = 6` rad/s, from which the DC motor follows as
in the OP3's truth: :math:`K = V / (\omega_{nl} N)` and :math:`R = N K V / \tau_{stall}`;
a rotor inertia of :math:`10^{-6} \max(1, m / 3\,\mathrm{kg})` kg·m² when the model
states no armature; inductance 0.1 mH; a current drive; a gear three times as stiff as the
servo (NAO's gears: 1200 N·m/rad on a 354 N·m/rad drive) with 0.25° of
backlash, damped by 5 % of critical on the reflected rotor inertia or, where more, by
:math:`c = k\,\Delta t` (NAO's gear: 1.0 N·m·s/rad on 1200 N·m/rad, a relaxation time of
0.83 physics steps), so that the gear's deflection under the lightest link it carries (a
swinging foot) stays resolved at the physics step (the spring is explicit, the damper
implicit in MuJoCo's ``implicitfast``: Apollo's 56 kN·m/rad ankle gears under a 1 kg foot
diverged with 5 % of critical); no flexible link. The template is checked to stand (tests).
Replace each ASSUMED value with the robot's when known.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from zmpkit.robots.robot_file import RobotFile
from zmpkit.robots.robot_file_reader import read_robot_file
from zmpkit.robots.user_model import UserModel, user_model
from zmpkit.robots.user_model_file import load_spec
from zmpkit.robots.user_walking import leg_length_m

__all__ = ["ASSUMED", "TruthTemplate", "truth_template", "write_truth_template"]

ASSUMED = "ASSUMED"
"""The mark of a value the model does not state."""
GEAR_RATIO = 200.0
SUPPLY_V = 12.0
NO_LOAD_SPEED_RAD_S = 6.0
INDUCTANCE_H = 1.0e-4
GEAR_STIFFNESS_PER_KP = 3.0
SATURATING_ERROR_RAD = 0.05
KD_PER_KP_S = 0.02
ROTOR_INERTIA_KG_M2 = 1.0e-6
ROTOR_REFERENCE_MASS_KG = 3.0
BACKLASH_RAD = 0.00436  # 0.25°
G = 9.81
MAX_SAG_RAD = 0.1
"""The softest model gain the template takes: the robot sags at most this under the
moment of its weight, m g h_CoM / kp (2.5 × NAO's drive) [rad]. A heuristic: a drive that
sags more cannot follow a walk whose leg joints move a few tenths of a radian. Menagerie's
Apollo, G1 and Berkeley Humanoid state learned policies' gains that sag 1.0, 0.46 and 14 rad
(each falls in zmpkit's walk with them); the OP3's (Menagerie's 21.1 N·m/rad, its factory
drive's 18.9) sag 0.40 and 0.45 rad, and its shipped truth walks only at half speed.
"""
HOLD_SAG_RAD = 0.04
"""The sag of the gain the template assumes in place of a softer one: NAO's drive holds
its weight's moment (13.5 N·m) within 0.038 rad (354 N·m/rad at its pitch joints) [rad]."""
GEAR_DAMPING_PER_CRITICAL = 0.05


@dataclass(frozen=True)
class TruthTemplate:
    """The template's text and how many of its values came from the model.

    Attributes:
        text: the truth YAML, each value's source in a comment.
        from_model: how many values the model states.
        assumed: how many are ASSUMED.
    """

    text: str
    from_model: int
    assumed: int


class _Values:
    """Values with their sources, in the order they are written."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.from_model = 0
        self.assumed = 0

    def add(self, key: str, value: float | str, source: str | None, indent: int = 2) -> None:
        """A ``key: value`` line; ``source`` None marks it ASSUMED."""
        text = f"{value:.6g}" if isinstance(value, float) else str(value)
        comment = f"from the model: {source}" if source else ASSUMED
        self.lines.append(f"{' ' * indent}{key}: {text}".ljust(40) + f"# {comment}")
        if source:
            self.from_model += 1
        else:
            self.assumed += 1


def _median(values: list[float]) -> float | None:
    return float(np.median(values)) if values else None


def _leg_facts(file: RobotFile) -> dict[str, float | None]:
    """What the model states about its leg joints' drives (module docstring)."""
    model = load_spec(file.model, file.packages).compile()
    kp, kd, torque, armature, friction = [], [], [], [], []
    for name in file.leg_joints:
        joint = model.joint(name).id
        dof = int(model.jnt_dofadr[joint])
        if model.jnt_actfrclimited[joint]:
            torque.append(float(np.max(np.abs(model.jnt_actfrcrange[joint]))))
        for a in range(model.nu):
            if model.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
                continue
            if int(model.actuator_trnid[a, 0]) != joint:
                continue
            gear = abs(float(model.actuator_gear[a, 0])) or 1.0
            if model.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_AFFINE:
                kp.append(float(model.actuator_gainprm[a, 0]) * gear)
                kd.append(-float(model.actuator_biasprm[a, 2]) * gear)
            if model.actuator_forcelimited[a]:
                torque.append(float(np.max(np.abs(model.actuator_forcerange[a]))) * gear)
        if model.dof_armature[dof] > 0.0:
            armature.append(float(model.dof_armature[dof]))
        if model.dof_frictionloss[dof] > 0.0:
            friction.append(float(model.dof_frictionloss[dof]))
    return {
        "kp": _median(kp),
        "kd": _median([v for v in kd if v > 0.0]),
        "torque": _median(torque),
        "armature": _median(armature),
        "friction": _median(friction),
    }


@dataclass(frozen=True)
class _Gain:
    """The drive's position gain and damping, with their sources (None: ASSUMED)."""

    kp: float
    kd: float
    kp_source: str | None
    kd_source: str | None
    note: str


def _position_gain(
    facts: dict[str, float | None], torque: float, weight_moment_n_m: float
) -> _Gain:
    """The model's position gain unless it lets the robot sag past :data:`MAX_SAG_RAD`.

    Args:
        facts: what the model states (:func:`_leg_facts`).
        torque: the stall torque at the joint [N·m].
        weight_moment_n_m: :math:`m g h_{CoM}`, the weight's moment about the soles [N·m].
    """
    kp, kd = facts["kp"], facts["kd"]
    if kp is None:
        gain = max(torque / SATURATING_ERROR_RAD, weight_moment_n_m / HOLD_SAG_RAD)
        return _Gain(
            gain, kd or KD_PER_KP_S * gain, None, "position actuator kv" if kd else None, ""
        )
    sag = weight_moment_n_m / kp
    if sag <= MAX_SAG_RAD:
        return _Gain(
            kp,
            kd or KD_PER_KP_S * kp,
            "position actuator kp",
            "position actuator kv" if kd else None,
            "",
        )
    gain = weight_moment_n_m / HOLD_SAG_RAD
    note = (
        f"  # the model's position gain {kp:.4g} N·m/rad would let the robot sag {sag:.2g} rad\n"
        f"  # under its weight's moment {weight_moment_n_m:.4g} N·m (more than {MAX_SAG_RAD:g} rad:"
        " a learned policy's\n"
        f"  # or a soft factory gain); ASSUMED: the gain that holds it within {HOLD_SAG_RAD:g}"
        " rad, as NAO's drive does"
    )
    return _Gain(gain, KD_PER_KP_S * gain, None, None, note)


def truth_template(file: RobotFile, built: UserModel, hip_height_m: float) -> TruthTemplate:
    """The truth template of ``file``'s robot (module docstring).

    Args:
        file: the robot file.
        built: the model zmpkit simulates (its mass and weight's moment).
        hip_height_m: the hips' height above the soles [m].
    """
    facts = _leg_facts(file)
    values = _Values()
    values.lines += [
        "# Truth of the effects of a robot-file robot (zmpkit robot truth init): the layout of",
        "# zmpkit.robots.servo_truth, SI units. Values marked ASSUMED are guesses: replace",
        "# them with the robot's own (datasheets, identification).",
    ]
    values.add("servo_rate_hz", 1.0 / file.timestep_s, "the physics rate", indent=0)
    torque = facts["torque"]
    torque_source = "forcerange / actuatorfrcrange" if torque else None
    if torque is None:
        torque = 0.5 * built.mass_kg * G * hip_height_m
    torque_constant = SUPPLY_V / (NO_LOAD_SPEED_RAD_S * GEAR_RATIO)
    resistance = GEAR_RATIO * torque_constant * SUPPLY_V / torque
    armature = facts["armature"]
    armature_source = "joint armature" if armature else None
    if armature is None:
        rotor = ROTOR_INERTIA_KG_M2 * max(1.0, built.mass_kg / ROTOR_REFERENCE_MASS_KG)
        armature = rotor * GEAR_RATIO**2
    drive = _position_gain(facts, torque, built.weight_moment_n_m)
    values.lines.append("motor:")
    values.add("gear_ratio", GEAR_RATIO, None)
    values.add("supply_voltage", SUPPLY_V, None)
    values.lines.append(
        f"  # stall torque {torque:.4g} N·m at the joint"
        + (" (from the model)" if torque_source else " ASSUMED: half the weight at hip height")
        + f"; no-load speed {NO_LOAD_SPEED_RAD_S:g} rad/s ASSUMED"
    )
    values.add("torque_constant", torque_constant, None)
    values.add("resistance", resistance, torque_source and "R = N K V / tau_stall")
    values.add("inductance", INDUCTANCE_H, None)
    values.add("rotor_inertia", armature / GEAR_RATIO**2, armature_source and "armature / N^2")
    values.add("drive", "current", None)
    values.lines.append("pid:")
    if drive.note:
        values.lines.append(drive.note)
    values.add("kp", drive.kp, drive.kp_source)
    values.add("ki", 0.0, None)
    values.add("kd", drive.kd, drive.kd_source)
    values.add("integral_limit_link", 0.05, None)
    friction = facts["friction"]
    values.lines.append("friction:")
    values.add("coulomb_link", friction or 0.0, "joint frictionloss" if friction else None)
    _add_gear(values, GEAR_STIFFNESS_PER_KP * drive.kp, armature, file.timestep_s)
    values.lines.append("flex: []                                # no flexible link ASSUMED")
    return TruthTemplate("\n".join(values.lines) + "\n", values.from_model, values.assumed)


def _add_gear(values: _Values, stiffness: float, armature: float, timestep_s: float) -> None:
    """The ``gear:`` section: stiffness [N·m/rad], damped as the module docstring says."""
    damping = max(
        2.0 * math.sqrt(stiffness * armature) * GEAR_DAMPING_PER_CRITICAL,
        stiffness * timestep_s,
    )
    values.lines.append("gear:")
    values.add("stiffness", stiffness, None)
    values.add("damping", damping, None)
    values.add("backlash", BACKLASH_RAD, None)
    values.add("inertia_link", 1.0e-3, None)


def write_truth_template(robot_file: str | Path, out: str | Path) -> TruthTemplate:
    """Write the truth template of the robot of ``robot_file`` to ``out`` (folders created).

    Raises:
        InputFileError: on a robot file with problems, one line each.
    """
    file = read_robot_file(robot_file)
    built = user_model(file)
    model = mujoco.MjModel.from_xml_string(built.mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    template = truth_template(file, built, leg_length_m(model, data, file))
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(template.text, encoding="utf-8")
    return template
