"""Assemble the virtual NAO: its rigid MJCF, the switched-on effects, and a simulation.

:func:`nao_robot` gives the :class:`~zmpkit.sim.description.RobotDescription` (a simulation
of it: :meth:`NAO.make_simulation <zmpkit.robots.robot.Robot.make_simulation>`); :func:`nao_ik_mjcf`
is the rigid kinematic model a controller (the IK) may use — the design, not the truth: it
has the URDF's torso mass and CoM, while the truth robot has its truth file's (effect C).

Joints whose motor effect is off are driven by the stiff ideal servo and keep the rotor's
reflected inertia ``J N²`` as joint ``armature``: the inertia is a property of the robot, not
of the motor effect, and it keeps a stiff servo on NAO's light links stable at 1 kHz.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco

from zmpkit.robots.nao.model import NAO_DRIVEN_JOINTS, NAO_SIDES, SOLE_PLATE_M, base_mjcf
from zmpkit.robots.nao.truth import NaoTruth, load_truth
from zmpkit.sim.builder import add_ideal_servo, find_element
from zmpkit.sim.description import FootSensor, RobotDescription
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.joint_effects import add_drive_effects, mjcf_with_flex
from zmpkit.sim.servo import ServoLimits

__all__ = [
    "NAO_CONTACT_FORCE_THRESHOLD_N",
    "NAO_SERVO_LIMITS",
    "nao_ik_mjcf",
    "nao_ik_model",
    "nao_mjcf",
    "nao_robot",
]

NAO_SERVO_LIMITS = ServoLimits(max_velocity=15.0, max_acceleration=5000.0, synchronized=False)
"""Setpoint limits of NAO's leg drives: the URDF velocity limit 6.40 rad/s; the acceleration
limit (ASSUMED) only smooths the 1 ms setpoint ramps the DCM interpolates."""
NAO_CONTACT_FORCE_THRESHOLD_N = 5.0
"""A NAO foot touches the floor while its vertical force is at least this [N]: about 10 % of
the robot's weight (5.2 kg), where TEO's 10 N would miss a lightly loaded foot."""
IK_TIMESTEP_S = 0.01
"""Timestep of the kinematic model [s] (unused by the IK, NAO's 10 ms motion frame)."""


def _resolve_truth(truth: NaoTruth | str | Path | None) -> NaoTruth:
    return truth if isinstance(truth, NaoTruth) else load_truth(truth)


def _ideal_servo(root: ET.Element, joint: str, params: NaoTruth) -> None:
    """Drive ``joint`` with the ideal servo, keeping the rotor's ``J N²`` (module docstring)."""
    joint_el = find_element(root, "joint", joint)
    armature = float(joint_el.get("armature", "0")) + params.motors[joint].armature_link
    joint_el.set("armature", f"{armature:.10g}")
    add_ideal_servo(root, joint, params.ideal_servo)


def nao_mjcf(effects: EffectSet | str = "all", truth: NaoTruth | str | Path | None = None) -> str:
    """NAO's MJCF text with the chosen effects applied, and the truth's real torso mass.

    Args:
        effects: ``"all"``, ``"none"``, letters such as ``"M,G,F"``, or an EffectSet.
        truth: truth parameters, a truth file, or ``None`` for the shipped truth.
    """
    on = EffectSet.parse(effects)
    params = _resolve_truth(truth)
    root = base_mjcf(1.0 / params.servo_rate_hz, params.floor_friction, params.torso_inertial())
    coupled = find_element(root, "joint", "RHipYawPitch")
    coupled.set("armature", f"{params.motors['LHipYawPitch'].armature_link:.10g}")
    for joint in NAO_DRIVEN_JOINTS:
        if not add_drive_effects(root, joint, on, params.motors, params.inductances, params.gear):
            _ideal_servo(root, joint, params)
    return mjcf_with_flex(root, on, params.flex)


def nao_ik_mjcf() -> str:
    """The rigid NAO without actuators: the kinematic and inertial model of the design."""
    root = base_mjcf(IK_TIMESTEP_S)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")


def nao_ik_model() -> mujoco.MjModel:
    """The compiled :func:`nao_ik_mjcf`, for :func:`~zmpkit.walking.ik.solve_walking_ik`."""
    return mujoco.MjModel.from_xml_string(nao_ik_mjcf())


def nao_robot(
    effects: EffectSet | str,
    truth: NaoTruth | str | Path | None,
    contact_force_threshold_n: float,
) -> RobotDescription:
    """The virtual NAO as a robot description, ready for :class:`~zmpkit.sim.world.Simulation`.

    NAO's :attr:`~zmpkit.robots.robot.Robot.describe`: ``effects`` as
    :meth:`~zmpkit.sim.effect_set.EffectSet.parse` reads them, ``truth`` the truth parameters,
    a truth file or ``None`` (the shipped truth), and the robot's contact threshold [N].
    """
    on = EffectSet.parse(effects)
    params = _resolve_truth(truth)
    feet = tuple(FootSensor.named(side, SOLE_PLATE_M) for side in NAO_SIDES)
    return RobotDescription(
        name="nao",
        mjcf=nao_mjcf(on, params),
        driven_joints=NAO_DRIVEN_JOINTS,
        feet=feet,
        effects=on,
        servo_limits=NAO_SERVO_LIMITS,
        sensor_params=params.sensors,
        ft_offsets=params.ft_offsets,
        contact_force_threshold_n=contact_force_threshold_n,
    )
