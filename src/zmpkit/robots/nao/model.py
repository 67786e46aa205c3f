"""The virtual NAO: a primitives-only MJCF built from ``nao-parameters.md``.

Bodies: a floating ``torso`` (the URDF base link) with two 6-DoF legs in NAO's joint order
(HipYawPitch, HipRoll, HipPitch, KneePitch, AnklePitch, AnkleRoll), and the head and both
arms held (welded, each lumped into one body; arms hanging, ShoulderPitch 1.57 rad). The
masses, CoMs and inertias are the URDF's, 5.305 kg in all. Geoms are capsules and boxes;
only the soles touch the floor. The truth robot replaces the torso's inertial with the real
one of its truth file (``torso``, effect C: CAD vs real); the design model keeps the URDF's.

HipYawPitch: NAO has one motor for both hip yaw-pitch joints (the right mimics the left).
The model keeps both joints and couples them with a joint equality ``R = L``; only the left
one is driven (:data:`NAO_DRIVEN_JOINTS` has 11 joints).

Feet: each sole is a 0.158 × 0.088 m box whose ankle projection lies 0.054 m from the heel
(its centre 0.025 m ahead of the ankle). The real NAO senses its feet with four FSRs each; the
virtual one carries a 6-axis F-T sensor (MuJoCo ``force`` + ``torque`` at a site) between the
foot and a thin sole plate :data:`SOLE_PLATE_M` thick, so the sensor sits that high above the
sole. Its wrench gives the same centre of pressure the FSRs estimate. The site
``zmpkit/{side}_sole`` marks the sole centre on the sole plane (the footstep planner's foot point).
A torso IMU (gyro, accelerometer, orientation) sits at the inertial unit's place.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING

from zmpkit.robots.nao import geometry as geo
from zmpkit.sim.names import FLOOR_GEOM, IMU_SITE, sole_site
from zmpkit.sim.sole_plate import SolePlate, add_sole_plate
from zmpkit.sim.standard_sensors import add_standard_sensors

if TYPE_CHECKING:
    from zmpkit.io.feet import FootMountEntry

__all__ = [
    "NAO_DRIVEN_JOINTS",
    "NAO_LEG_JOINTS",
    "NAO_MASS_KG",
    "NAO_SIDES",
    "NAO_WALKING_COM_HEIGHT_M",
    "NAO_WALK_COM_HEIGHT_M",
    "SOLE_PLATE_M",
    "SOLE_PLATE_MASS_KG",
    "ZERO_POSE_TORSO_HEIGHT_M",
    "base_mjcf",
    "link_body",
    "nao_feet_mounts",
    "side_letter",
]

NAO_MASS_KG = 5.305
"""Total mass of the 25 massive URDF links [kg] (parameters file §1)."""
NAO_WALKING_COM_HEIGHT_M = 0.26
"""CoM height of the 3D-LIPM walk (Dortmund ZMP/IP controller) [m] (§1)."""
NAO_WALK_COM_HEIGHT_M = 0.25
"""CoM height of zmpkit's walk [m]. NAO's crouch CoM is 0.26 m (nao-parameters.md §1), but 0.1 m
steps at 0.26 m stretch the trailing leg to its full length; 0.25 m keeps the knee bent."""
SOLE_PLATE_M = 0.005
"""Thickness of the sole plate below the F-T sensor = sensor height above the sole [m]."""
SOLE_PLATE_MASS_KG = 0.015
"""Mass of the sole plate, taken from the foot link; the sensor does not weigh it [kg]."""
ZERO_POSE_TORSO_HEIGHT_M = (
    geo.HIP_OFFSET_Z_M + geo.THIGH_LENGTH_M + geo.TIBIA_LENGTH_M + geo.ANKLE_TO_SOLE_M
)
"""Torso origin above the sole, legs straight [m] (0.33301, §1)."""
NAO_SIDES: tuple[str, str] = ("left", "right")
NAO_LEG_JOINTS: tuple[str, ...] = tuple(
    f"{letter}{j.stem}" for letter in ("L", "R") for j in geo.LEG_JOINTS
)
"""All twelve leg joints, left leg then right leg, hip to ankle."""
NAO_DRIVEN_JOINTS: tuple[str, ...] = tuple(j for j in NAO_LEG_JOINTS if j != "RHipYawPitch")
"""The joints with a motor (RHipYawPitch follows LHipYawPitch)."""

_LINK_BODY = {
    "HipYawPitch": "Pelvis",
    "HipRoll": "Hip",
    "HipPitch": "Thigh",
    "KneePitch": "Tibia",
    "AnklePitch": "Ankle",
    "AnkleRoll": "Foot",
}
_SEGMENT_LENGTH_M = {"HipPitch": geo.THIGH_LENGTH_M, "KneePitch": geo.TIBIA_LENGTH_M}
_SOLE_SOLREF = "0.005 1"
_SOLE_SOLIMP = "0.9 0.95 0.001"
_VISUAL = {"contype": "0", "conaffinity": "0", "group": "1", "mass": "0"}


def _f(*values: float) -> str:
    return " ".join(f"{v:.10g}" for v in values)


def side_letter(side: str) -> str:
    """``"left"`` → ``"L"``, ``"right"`` → ``"R"``."""
    return "L" if side == "left" else "R"


def link_body(side: str, stem: str) -> str:
    """Name of the body moved by joint ``stem`` of a leg, e.g. ``("left", "HipPitch")`` → LThigh."""
    return side_letter(side) + _LINK_BODY[stem]


def _body(parent: ET.Element, name: str, pos: tuple[float, ...]) -> ET.Element:
    return ET.SubElement(parent, "body", {"name": name, "pos": _f(*pos)})


def _inertial(body: ET.Element, inertial: geo.Inertial, mass: float | None = None) -> None:
    ET.SubElement(
        body,
        "inertial",
        {
            "pos": _f(*inertial.com),
            "mass": _f(inertial.mass if mass is None else mass),
            "diaginertia": _f(*inertial.inertia),
        },
    )


def _capsule(body: ET.Element, start: tuple[float, ...], end: tuple[float, ...], r: float) -> None:
    ET.SubElement(
        body, "geom", {"type": "capsule", "fromto": _f(*start, *end), "size": _f(r), **_VISUAL}
    )


def _leg(torso: ET.Element, side: str, friction: float) -> None:
    sign = 1.0 if side == "left" else -1.0
    parent = torso
    for joint in geo.LEG_JOINTS:
        x, y, z = joint.origin
        body = _body(parent, link_body(side, joint.stem), (x, sign * y, z))
        link = geo.LEG_LINKS[joint.stem]
        link = link if side == "left" else link.mirrored()
        foot = joint.stem == "AnkleRoll"
        _inertial(body, link, link.mass - SOLE_PLATE_MASS_KG if foot else None)
        ax, ay, az = joint.axis
        axis = (ax, ay, az) if side == "left" else (ax, ay, -az)
        lo, hi = joint.range_left if side == "left" else joint.range_right
        name = side_letter(side) + joint.stem
        ET.SubElement(
            body, "joint", {"name": name, "type": "hinge", "axis": _f(*axis), "range": _f(lo, hi)}
        )
        if joint.stem in _SEGMENT_LENGTH_M:
            _capsule(body, (0, 0, 0), (0, 0, -_SEGMENT_LENGTH_M[joint.stem]), 0.03)
        parent = body
    _sole(parent, side, friction)


def _sole(foot: ET.Element, side: str, friction: float) -> None:
    """Sole plate under the ankle: F-T site, contact box, sole-centre site."""
    h = SOLE_PLATE_M
    z_ft = -(geo.ANKLE_TO_SOLE_M - h)
    _capsule(foot, (0, 0, 0), (0, 0, z_ft + 0.01), 0.02)
    sole = _body(foot, side_letter(side) + "Sole", (0.0, 0.0, z_ft))
    plate = SolePlate(
        geo.SOLE_LENGTH_M,
        geo.SOLE_WIDTH_M,
        h,
        geo.SOLE_CENTRE_AHEAD_OF_ANKLE_M,
        SOLE_PLATE_MASS_KG,
        friction,
        _SOLE_SOLREF,
        _SOLE_SOLIMP,
    )
    add_sole_plate(sole, side, plate, centre_site=sole_site(side))


def _upper_body(torso: ET.Element, inertial: geo.Inertial) -> None:
    """Torso inertial and visuals, the IMU site, the welded head and arms."""
    _inertial(torso, inertial)
    ET.SubElement(
        torso, "geom", {"type": "box", "pos": "-0.005 0 0.04", "size": "0.04 0.06 0.07", **_VISUAL}
    )
    ET.SubElement(
        torso, "site", {"name": IMU_SITE, "pos": _f(*geo.IMU_POSITION_M), "size": "0.005"}
    )
    head = _body(torso, "Head", geo.HEAD_ORIGIN_M)
    _inertial(head, geo.HEAD)
    ET.SubElement(head, "geom", {"type": "sphere", "pos": "0 0 0.05", "size": "0.055", **_VISUAL})
    for side, sign in (("left", 1.0), ("right", -1.0)):
        shoulder = (0.0, sign * geo.SHOULDER_OFFSET_Y_M, geo.SHOULDER_OFFSET_Z_M)
        arm = _body(torso, side_letter(side) + "Arm", shoulder)
        _inertial(arm, geo.ARM if side == "left" else geo.ARM.mirrored())
        _capsule(arm, (0, 0, 0), (0, 0, -0.17), 0.025)


def base_mjcf(
    timestep_s: float = 0.001, floor_friction: float = 1.0, torso: geo.Inertial = geo.TORSO
) -> ET.Element:
    """The rigid NAO (no effects, no actuators) on a floor, as an MJCF element tree.

    The torso starts at its zero-pose height (legs straight, soles on the floor).

    Args:
        timestep_s: physics timestep [s].
        floor_friction: sole–floor sliding friction coefficient [-].
        torso: the torso link's mass [kg], CoM in the torso frame [m] and inertia at the
            CoM [kg·m²]; the URDF's by default (the design), the real one for the truth.
    """
    mujoco = ET.Element("mujoco", {"model": "nao"})
    ET.SubElement(mujoco, "compiler", {"angle": "radian", "autolimits": "true"})
    ET.SubElement(
        mujoco,
        "option",
        {"timestep": _f(timestep_s), "integrator": "implicitfast", "cone": "elliptic"},
    )
    world = ET.SubElement(mujoco, "worldbody")
    ET.SubElement(world, "light", {"pos": "0 0 2", "dir": "0 0 -1"})
    ET.SubElement(
        world,
        "geom",
        {"name": FLOOR_GEOM, "type": "plane", "size": "10 10 0.1", "rgba": "0.8 0.8 0.8 1"},
    )
    base = _body(world, "torso", (0.0, 0.0, ZERO_POSE_TORSO_HEIGHT_M))
    ET.SubElement(base, "freejoint", {"name": "root"})
    _upper_body(base, torso)
    for side in NAO_SIDES:
        _leg(base, side, floor_friction)
    equality = ET.SubElement(mujoco, "equality")
    ET.SubElement(
        equality,
        "joint",
        {"name": "hip_yaw_pitch_coupling", "joint1": "RHipYawPitch", "joint2": "LHipYawPitch"},
    )
    add_standard_sensors(mujoco, NAO_SIDES)
    return mujoco


def nao_feet_mounts() -> dict[str, FootMountEntry]:
    """NAO's foot F-T sensor mounts in the world frame, zero pose (soles on z = 0).

    Returns:
        ``{"left": {"position": [x, y, z], "rpy": [r, p, y], "sole_height": h}, "right": ...}``
        with the sensor origin [m] (under the ankle), its roll-pitch-yaw [rad] (axes x
        forward, y left, z up) and its height above the sole [m].
    """
    h = SOLE_PLATE_M
    return {
        side: {
            "position": [0.0, sign * geo.HIP_OFFSET_Y_M, h],
            "rpy": [0.0, 0.0, 0.0],
            "sole_height": h,
        }
        for side, sign in (("left", 1.0), ("right", -1.0))
    }
