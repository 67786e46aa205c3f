"""The MJCF of a user's robot: their MJCF or URDF, loaded by MuJoCo, plus zmpkit's sensors.

MuJoCo's own loader (:class:`mujoco.MjSpec`) reads the file, MJCF or URDF alike
(:mod:`zmpkit.robots.user_model_file`); the names the robot file gives are checked
(:mod:`zmpkit.robots.user_model_names`) and the feet found (:mod:`zmpkit.robots.user_feet`).
Then:

0. geoms whose mesh file does not exist are dropped with their meshes (a URDF published
   without its meshes, e.g. for licence reasons): the links keep their ``<inertial>`` masses,
   the collision left is the model's primitive shapes (a foot needs at least one);
1. a free joint is added at the root body when the model has none (a URDF's usual case);
2. each foot gets a sole plate (:mod:`zmpkit.sim.sole_plate`): a body under the foot, aligned
   with the world at the initial pose, whose top carries the F-T site ``zmpkit/{side}_ft`` and whose
   box is the only contact of the foot with the floor (the foot's own geoms stop colliding);
3. the root is lifted so the plates rest on the floor (a plane, added if the model has none);
4. an IMU site on the IMU body, the force, torque, gyro, accelerometer and orientation
   sensors, and one ideal servo per leg joint replace the model's own actuators (and the
   actuator defaults of its ``<default>`` classes: a ``ctrlrange`` or ``forcerange`` meant
   for the model's position servos would clip zmpkit's servos and motors); the other joints
   (arms, head) are held at their initial angles by joint springs as stiff as the servos
   (``stiffness`` = the servo's kp, ``damping`` at least its kd), as the robot's own servos
   would hold them; every servo or spring joint gets at least the armature (reflected rotor
   inertia) that keeps it stable (:data:`STIFFNESS_STEPS`).

The robot's mass, footprint and standing pose come from the compiled model: a user gives
names, not numbers.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import mujoco
import numpy as np

from zmpkit.robots.robot_file import SIDES, RobotFile
from zmpkit.robots.user_feet import FootPrint, footprint, subtree_bodies
from zmpkit.robots.user_model_file import (
    compile_spec,
    exclude_initial_self_contacts,
    face_world_x,
    load_spec,
    root_body,
)
from zmpkit.robots.user_model_names import check_names
from zmpkit.sim.builder import add_ideal_servo
from zmpkit.sim.drive import IdealServoParams
from zmpkit.sim.names import FLOOR_GEOM, IMU_SITE, ft_plate_body, ft_site, sole_site
from zmpkit.sim.sole_plate import SolePlate, add_sole_plate
from zmpkit.sim.standard_sensors import add_standard_sensors

__all__ = ["ACTUATOR_TAGS", "STIFFNESS_STEPS", "UserModel", "user_model"]

_FLOOR_FRICTION = 1.0
_FLOOR_CONTACT = {"contype": "1", "conaffinity": "1", "condim": "3", "margin": "0", "gap": "0"}
"""The floor's collision attributes, explicit: the model's geom defaults are not the floor's."""
_SOLREF = "0.005 1"
_SOLIMP = "0.9 0.95 0.001"
_PLATE_MASS_FRACTION = 0.002
ACTUATOR_TAGS = frozenset(
    {
        "general",
        "motor",
        "position",
        "velocity",
        "intvelocity",
        "damper",
        "cylinder",
        "muscle",
        "adhesion",
        "plugin",
        "dcmotor",
        "pid",
    }
)
"""The MJCF actuator elements (and their ``<default>`` entries) a user's model may carry."""
STIFFNESS_STEPS = 0.2
"""A servo joint's armature is at least ``kp dt² / STIFFNESS_STEPS²``: the servo's natural
period then spans at least ``2π / STIFFNESS_STEPS`` ≈ 31 physics steps, so the explicit
position gain stays stable on light links (a servo's reflected rotor inertia) [-]."""


@dataclass(frozen=True)
class UserModel:
    """The user's robot as zmpkit simulates it.

    Attributes:
        mjcf: the MJCF text with the sole plates, sensors and servos.
        feet: side → its footprint.
        mass_kg: total mass [kg].
        servo: the ideal servos' gains.
        weight_moment_n_m: :math:`m g h_{CoM}`, the weight's moment about the soles at the
            initial pose, the sole plates left out [N·m].
        excluded_contacts: the pairs of bodies whose geoms already touch at the initial pose
            (overlapping links of an imported model), whose contacts zmpkit excludes.
    """

    mjcf: str
    feet: dict[str, FootPrint]
    mass_kg: float
    servo: IdealServoParams
    weight_moment_n_m: float
    excluded_contacts: tuple[tuple[str, str], ...] = ()


def _weight_moment_n_m(model: mujoco.MjModel, data: mujoco.MjData, sole_z: float) -> float:
    """:math:`m g h_{CoM}`, the weight's moment about the soles at ``sole_z`` [N·m]."""
    height = float(data.subtree_com[0][2]) - sole_z
    return float(model.body_subtreemass[0]) * 9.81 * height


def _servo(robot: RobotFile, weight_moment: float) -> IdealServoParams:
    """The ideal servo: the file's gains, else scaled from weight × CoM height [N·m]."""
    kp = robot.servo.get("kp", 100.0 * weight_moment)
    return IdealServoParams(
        kp=kp, ki=robot.servo.get("ki", kp), kd=robot.servo.get("kd", 0.005 * kp)
    )


def _add_plate(
    spec: mujoco.MjSpec, data: mujoco.MjData, side: str, foot: FootPrint, h: float
) -> None:
    """The sole plate body under the foot, world-aligned, its top on the foot's bottom."""
    body = spec.body(foot.body)
    xpos, xmat = data.body(foot.body).xpos, data.body(foot.body).xmat.reshape(3, 3)
    top = np.array([foot.centre_m[0], foot.centre_m[1], foot.bottom_z_m])
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, xmat.T.flatten())
    plate = body.add_body(name=ft_plate_body(side), pos=xmat.T @ (top - xpos), quat=quat)
    plate.add_site(name=ft_site(side), size=[0.005, 0.005, 0.005])
    plate.add_site(name=sole_site(side), pos=[0.0, 0.0, -h], size=[0.005, 0.005, 0.005])


def user_model(robot: RobotFile) -> UserModel:
    """Build the MJCF zmpkit simulates for ``robot`` (module docstring).

    Raises:
        InputFileError: naming the robot file or the model on any problem.
    """
    spec = load_spec(robot.model, robot.packages)
    if robot.forward != "+x":
        face_world_x(spec, robot.forward, compile_spec(robot, spec)[0])
    model, data = compile_spec(robot, spec)
    check_names(robot, model)
    excluded = exclude_initial_self_contacts(spec, model, data)
    feet = {side: footprint(robot, model, data, side) for side in SIDES}
    mass = float(model.body_subtreemass[0])
    weight_moment = _weight_moment_n_m(model, data, min(f.bottom_z_m for f in feet.values()))
    servo = _servo(robot, weight_moment)
    h = robot.sole_height_m
    for side, foot in feet.items():
        for b in subtree_bodies(model, model.body(foot.body).id):
            for geom in spec.body(model.body(b).name).geoms:
                geom.contype, geom.conaffinity = 0, 0
        _add_plate(spec, data, side, foot, h)
    lift = h - min(f.bottom_z_m for f in feet.values())
    root = spec.worldbody.first_body()
    root.pos = [root.pos[0], root.pos[1], root.pos[2] + lift]
    spec.option.timestep = robot.timestep_s
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    xml = ET.fromstring(spec.to_xml())
    _finish_xml(xml, robot, feet, mass, servo, root_body(model))
    ET.indent(xml)
    mjcf = ET.tostring(xml, encoding="unicode")
    return UserModel(mjcf, feet, mass, servo, weight_moment, excluded)


def _finish_xml(
    xml: ET.Element,
    robot: RobotFile,
    feet: dict[str, FootPrint],
    mass: float,
    servo: IdealServoParams,
    root: str,
) -> None:
    """Plates' geoms, floor, IMU site, sensors and servos, on the MJCF tree."""
    bodies = {b.get("name"): b for b in xml.iter("body")}
    h = robot.sole_height_m
    for side, foot in feet.items():
        plate = SolePlate(
            foot.length_m,
            foot.width_m,
            h,
            0.0,
            max(_PLATE_MASS_FRACTION * mass, 1e-3),
            _FLOOR_FRICTION,
            _SOLREF,
            _SOLIMP,
        )
        body = bodies[ft_plate_body(side)]
        for site in list(body.iter("site")):
            body.remove(site)
        add_sole_plate(body, side, plate, centre_site=sole_site(side))
    world = xml.find("worldbody")
    assert world is not None
    if not any(g.get("type") == "plane" for g in world.findall("geom")):
        floor = {"name": FLOOR_GEOM, "type": "plane", "size": "5 5 0.1", **_FLOOR_CONTACT}
        ET.SubElement(world, "geom", floor)
    imu = bodies[robot.imu or root]
    ET.SubElement(imu, "site", {"name": IMU_SITE, "size": "0.01"})
    for old in xml.findall("actuator") + xml.findall("sensor") + xml.findall("keyframe"):
        xml.remove(old)
    for default in xml.iter("default"):
        for entry in [e for e in default if e.tag in ACTUATOR_TAGS]:
            default.remove(entry)
    add_standard_sensors(xml, SIDES)
    minimum = servo.kp * robot.timestep_s**2 / STIFFNESS_STEPS**2
    for joint in robot.leg_joints:
        add_ideal_servo(xml, joint, servo)
    for element in xml.iter("joint"):
        name = element.get("name")
        if name is None or element.get("type", "hinge") not in ("hinge", "slide"):
            continue
        if name not in robot.leg_joints:  # held where it starts, as a servo would hold it
            element.set("stiffness", f"{servo.kp:.9g}")
            element.set("springref", element.get("ref", "0"))
            element.set("damping", f"{max(float(element.get('damping', '0')), servo.kd):.9g}")
        armature = max(float(element.get("armature", "0")), minimum)
        element.set("armature", f"{armature:.9g}")
