"""The virtual TEO: a primitives-only MJCF built from ``teo-parameters.md``.

Bodies: a floating root waist (pelvis) with two 6-DoF legs in TEO's joint order (axial hip
z, sagittal hip x, frontal hip y, knee y, frontal ankle y, sagittal ankle x), a two-joint
waist (axial z, frontal y) carrying the trunk, and head and arms held fixed (welded, their
six links lumped per arm). Geoms are capsules and boxes; only the soles touch the floor.

Feet: each sole is a 0.245 × 0.140 m box whose ankle projection lies 0.07 m from the heel,
laterally centred (the parameters file leaves the end unverified; we take the heel). A
JR3-like 6-axis F-T sensor (MuJoCo ``force`` + ``torque`` at a site) sits between the foot
and the sole, :data:`~zmpkit.robots.teo.geometry.FT_HEIGHT_ABOVE_SOLE_M` ≈ 0.010 m above the
sole — the height implied by the SDF (0.113 m below the ankle); the balance code's 0.03225 m
and older 0.0194 m disagree. Everything above the sensor, foot included, is measured; the
sole plate below it weighs :data:`SOLE_PLATE_MASS_KG`.

Mass reconciliation: the manual's links sum to 55.9 kg with the CoM 0.859 m above the sole,
while the paper's balance model (and the public DLIPM code) uses 62.6 kg at 0.893 m. We add
the missing mass as one point mass in the trunk (``payload`` in the truth file: batteries or
the waiter tray — no source says which), placed on the trunk axis so the standing-pose CoM
height becomes 0.893 m; it sits at about 1.18 m above the sole, as the parameters file
computes for a single point mass.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING

from zmpkit.robots.teo import geometry as geo
from zmpkit.robots.teo.truth import TeoTruth
from zmpkit.sim.names import FLOOR_GEOM, IMU_SITE, sole_site
from zmpkit.sim.sole_plate import SolePlate, add_sole_plate
from zmpkit.sim.standard_sensors import add_standard_sensors

if TYPE_CHECKING:
    from zmpkit.io.feet import FootMountEntry

__all__ = [
    "FLOOR_FRICTION",
    "SOLE_PLATE_MASS_KG",
    "TEO_BALANCE_MASS_KG",
    "TEO_COM_HEIGHT_M",
    "TEO_DRIVEN_JOINTS",
    "TEO_SIDES",
    "base_mjcf",
    "teo_feet_mounts",
]

TEO_BALANCE_MASS_KG = 62.6
"""Mass of the balance model the controller believes (paper A §4.1) [kg]."""
TEO_COM_HEIGHT_M = 0.893
"""CoM height above the ground of the balance model (paper A §4.1) [m]."""
SOLE_PLATE_MASS_KG = 0.02
"""Mass below each F-T sensor (sole plate), which the sensor does not weigh [kg]."""
FLOOR_FRICTION = 1.0
"""Sliding friction coefficient sole–floor [-]."""
TEO_SIDES: tuple[str, str] = ("right", "left")
TEO_DRIVEN_JOINTS: tuple[str, ...] = (
    *(f"right_{j.stem}" for j in geo.LEG_JOINTS),
    *(f"left_{j.stem}" for j in geo.LEG_JOINTS),
    "trunk_axial",
    "trunk_frontal",
)
"""The joints the servos drive, in TEO's order: right leg 0…5, left leg 0…5, trunk 0…1."""

_SOLE_CONTACT_SOLREF = "0.004 1"
_SOLE_CONTACT_SOLIMP = "0.9 0.95 0.001"
_VISUAL = {"contype": "0", "conaffinity": "0", "group": "1", "mass": "0"}


def _f(*values: float) -> str:
    return " ".join(f"{v:.10g}" for v in values)


def _body(parent: ET.Element, name: str, pos: tuple[float, float, float]) -> ET.Element:
    return ET.SubElement(parent, "body", {"name": name, "pos": _f(*pos)})


def _inertial(body: ET.Element, inertial: geo.Inertial) -> None:
    ET.SubElement(
        body,
        "inertial",
        {
            "pos": _f(*inertial.com),
            "mass": _f(inertial.mass),
            "fullinertia": _f(*inertial.inertia),
        },
    )


def _capsule(body: ET.Element, start: tuple[float, ...], end: tuple[float, ...], r: float) -> None:
    ET.SubElement(
        body, "geom", {"type": "capsule", "fromto": _f(*start, *end), "size": _f(r), **_VISUAL}
    )


def _hinge(body: ET.Element, name: str, axis: tuple[float, ...], rng: tuple[float, float]) -> None:
    lo, hi = (math.radians(a) for a in rng)
    ET.SubElement(
        body,
        "joint",
        {"name": name, "type": "hinge", "axis": _f(*axis), "range": _f(lo, hi), "limited": "true"},
    )


def _mirror_range(
    side: str, rng: tuple[float, float], axis: tuple[float, ...]
) -> tuple[float, float]:
    """Left-leg limits: roll (x) and yaw (z) mirror; pitch (y) keeps the right's."""
    if side == "left" and axis[1] == 0.0:
        return (-rng[1], -rng[0])
    return rng


def _leg(root: ET.Element, side: str) -> None:
    sign = -1.0 if side == "right" else 1.0
    links = geo.LEG_LINKS[side]
    offsets = {
        "hip_axial": (0.0, sign * geo.HIP_LATERAL_M, 0.0),
        "hip_sagittal": (0.0, 0.0, -geo.HIP_DROP_M),
        "hip_frontal": (0.0, 0.0, 0.0),
        "knee_frontal": (0.0, 0.0, -geo.THIGH_M),
        "ankle_frontal": (0.0, -sign * geo.KNEE_TO_ANKLE_LATERAL_M, -geo.SHANK_M),
        "ankle_sagittal": (0.0, 0.0, 0.0),
    }
    parent = root
    for joint in geo.LEG_JOINTS:
        body = _body(parent, f"{side}_{joint.stem}", offsets[joint.stem])
        _inertial(body, links[joint.stem])
        _hinge(
            body,
            f"{side}_{joint.stem}",
            joint.axis,
            _mirror_range(side, joint.range_deg, joint.axis),
        )
        parent = body
    _leg_visuals(root, side)
    _foot(parent, side)


def _leg_visuals(root: ET.Element, side: str) -> None:
    for body in root.iter("body"):
        name = body.get("name", "")
        if name == f"{side}_hip_axial":
            _capsule(body, (0, 0, 0), (0, 0, -geo.HIP_DROP_M), 0.04)
        elif name == f"{side}_hip_frontal":
            _capsule(body, (0, 0, 0), (0, 0, -geo.THIGH_M), 0.05)
        elif name == f"{side}_knee_frontal":
            _capsule(body, (0, 0, 0), (0, 0, -geo.SHANK_M), 0.045)


def _foot(ankle: ET.Element, side: str) -> None:
    """Sole body under the ankle: F-T site, sole box, contact."""
    z_ft = -(geo.ANKLE_TO_SOLE_M - geo.FT_HEIGHT_ABOVE_SOLE_M)
    _capsule(ankle, (0, 0, 0), (0, 0, z_ft), 0.03)
    sole = _body(ankle, f"{side}_sole", (0.0, 0.0, z_ft))
    plate = SolePlate(
        geo.SOLE_LENGTH_M,
        geo.SOLE_WIDTH_M,
        geo.FT_HEIGHT_ABOVE_SOLE_M,
        0.5 * (geo.ANKLE_TO_TOE_M - geo.HEEL_TO_ANKLE_M),
        SOLE_PLATE_MASS_KG,
        FLOOR_FRICTION,
        _SOLE_CONTACT_SOLREF,
        _SOLE_CONTACT_SOLIMP,
    )
    add_sole_plate(sole, side, plate, centre_site=sole_site(side))


def _trunk(root: ET.Element, truth: TeoTruth) -> None:
    """Waist joints, trunk, fixed head and arms, and the reconciling payload mass."""
    axial = _body(root, "trunk_axial", (0.0, 0.0, geo.ROOT_TO_TRUNK_JOINTS_M))
    _inertial(axial, geo.TRUNK_LINKS["trunk_axial"])
    _hinge(axial, "trunk_axial", (0.0, 0.0, 1.0), (-51.32, 51.32))
    trunk = _body(axial, "trunk_frontal", (0.0, 0.0, 0.0))
    _inertial(trunk, geo.TRUNK_LINKS["trunk_frontal"])
    _hinge(trunk, "trunk_frontal", (0.0, 1.0, 0.0), (-95.41, 15.11))
    shoulder_z = geo.ROOT_TO_SHOULDER_M - geo.ROOT_TO_TRUNK_JOINTS_M
    ET.SubElement(
        trunk,
        "geom",
        {"type": "box", "pos": _f(0.02, 0, 0.2), "size": "0.09 0.2 0.15", **_VISUAL},
    )
    ET.SubElement(trunk, "site", {"name": IMU_SITE, "pos": _f(0.0, 0.0, 0.1), "size": "0.01"})
    for name, (height, inertial) in geo.HEAD_LINKS.items():
        head = _body(trunk, name, (0.0, 0.0, height - geo.ROOT_TO_TRUNK_JOINTS_M))
        _inertial(head, inertial)
    ET.SubElement(
        trunk, "geom", {"type": "sphere", "pos": _f(0, 0, 0.53), "size": "0.09", **_VISUAL}
    )
    for side, sign in (("right", -1.0), ("left", 1.0)):
        arm = _body(trunk, f"{side}_arm", (0.0, sign * geo.SHOULDER_LATERAL_M, shoulder_z))
        com = (geo.ARM.com[0], -sign * geo.ARM.com[1], geo.ARM.com[2])
        ixx, iyy, izz, ixy, ixz, iyz = geo.ARM.inertia
        mirrored = (ixx, iyy, izz, ixy, ixz, -sign * iyz)
        _inertial(arm, geo.Inertial(geo.ARM.mass, com, mirrored))
        _capsule(arm, (0, sign * 0.084, 0), (0, sign * 0.084, -0.55), 0.04)
    payload = _body(trunk, "payload", truth.payload_position_m)
    ET.SubElement(
        payload,
        "inertial",
        {"pos": "0 0 0", "mass": _f(truth.payload_mass_kg), "diaginertia": "1e-4 1e-4 1e-4"},
    )


def base_mjcf(truth: TeoTruth) -> ET.Element:
    """The rigid TEO (no effects applied) standing on a floor, as an MJCF element tree.

    The root waist starts at its standing height (sole on the floor, legs straight).
    """
    mujoco = ET.Element("mujoco", {"model": "teo"})
    ET.SubElement(mujoco, "compiler", {"angle": "radian", "autolimits": "true"})
    ET.SubElement(
        mujoco,
        "option",
        {
            "timestep": _f(1.0 / truth.servo_rate_hz),
            "integrator": "implicitfast",
            "cone": "elliptic",
        },
    )
    world = ET.SubElement(mujoco, "worldbody")
    ET.SubElement(world, "light", {"pos": "0 0 3", "dir": "0 0 -1"})
    ET.SubElement(
        world,
        "geom",
        {"name": FLOOR_GEOM, "type": "plane", "size": "5 5 0.1", "rgba": "0.8 0.8 0.8 1"},
    )
    z_root = geo.ANKLE_TO_SOLE_M + geo.SHANK_M + geo.THIGH_M + geo.HIP_DROP_M
    root = _body(world, "root_waist", (0.0, 0.0, z_root))
    ET.SubElement(root, "freejoint", {"name": "root"})
    _inertial(root, geo.TRUNK_LINKS["root_waist"])
    ET.SubElement(root, "geom", {"type": "box", "size": "0.08 0.18 0.05", **_VISUAL})
    for side in TEO_SIDES:
        _leg(root, side)
    _trunk(root, truth)
    add_standard_sensors(mujoco, TEO_SIDES)
    return mujoco


def teo_feet_mounts() -> dict[str, FootMountEntry]:
    """TEO's foot F-T sensor mounts in the world frame, standing pose (soles on z = 0).

    Returns:
        ``{"right": {"position": [x, y, z], "rpy": [r, p, y], "sole_height": h}, "left": ...}``
        with the sensor origin [m], its roll-pitch-yaw [rad] (axes x forward, y left, z up)
        and its height above the sole [m].
    """
    y_ankle = geo.HIP_LATERAL_M - geo.KNEE_TO_ANKLE_LATERAL_M
    h = geo.FT_HEIGHT_ABOVE_SOLE_M
    return {
        side: {"position": [0.0, sign * y_ankle, h], "rpy": [0.0, 0.0, 0.0], "sole_height": h}
        for side, sign in (("right", -1.0), ("left", 1.0))
    }
