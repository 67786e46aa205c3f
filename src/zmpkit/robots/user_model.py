"""The MJCF of a user's robot: their MJCF or URDF, loaded by MuJoCo, plus zmpkit's sensors.

MuJoCo's own loader (:class:`mujoco.MjSpec`) reads the file, MJCF or URDF alike. Then:

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

import math
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit._validate import list_some, shorten
from zmpkit.errors import InputFileError
from zmpkit.robots.package_uris import resolve_package_uris
from zmpkit.robots.problems import Problems
from zmpkit.robots.robot_file import SIDES, RobotFile
from zmpkit.sim.builder import add_ideal_servo
from zmpkit.sim.effects import IdealServoParams
from zmpkit.sim.names import FLOOR_GEOM, IMU_SITE, NAMESPACE, ft_plate_body, ft_site, sole_site
from zmpkit.sim.sole_plate import SolePlate, add_sole_plate
from zmpkit.sim.standard_sensors import add_standard_sensors

__all__ = [
    "ACTUATOR_TAGS",
    "COLLISION_GROUP",
    "YAW_TO_FACE_X_RAD",
    "FootPrint",
    "UserModel",
    "body_names",
    "check_names",
    "collision_geoms",
    "compile_model",
    "drop_missing_meshes",
    "face_world_x",
    "foot_body",
    "footprint",
    "geom_corners",
    "load_spec",
    "name_problems",
    "root_body",
    "user_model",
]

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
class FootPrint:
    """A foot's sole at the initial pose, world frame.

    Attributes:
        body: the foot's body.
        centre_m: sole centre (x, y) [m].
        bottom_z_m: lowest point of the foot's collision geoms [m].
        length_m: sole length along x [m].
        width_m: sole width along y [m].
    """

    body: str
    centre_m: tuple[float, float]
    bottom_z_m: float
    length_m: float
    width_m: float


@dataclass(frozen=True)
class UserModel:
    """The user's robot as zmpkit simulates it.

    Attributes:
        mjcf: the MJCF text with the sole plates, sensors and servos.
        feet: side → its footprint.
        mass_kg: total mass [kg].
        servo: the ideal servos' gains.
        excluded_contacts: the pairs of bodies whose geoms already touch at the initial pose
            (overlapping links of an imported model), whose contacts zmpkit excludes.
    """

    mjcf: str
    feet: dict[str, FootPrint]
    mass_kg: float
    servo: IdealServoParams
    excluded_contacts: tuple[tuple[str, str], ...] = ()


def load_spec(model_file: Path, packages: Mapping[str, Path] | None = None) -> mujoco.MjSpec:
    """The model (MJCF or URDF) as MuJoCo loads it, with a free joint at the root.

    Args:
        model_file: the MJCF or URDF file.
        packages: package name → folder, for ``package://`` mesh files
            (:mod:`zmpkit.robots.package_uris`).

    Raises:
        InputFileError: naming the model file if MuJoCo cannot load it, or a mesh's package
            that is not found.
    """
    try:
        spec = mujoco.MjSpec.from_file(str(model_file))
    except (ValueError, mujoco.FatalError) as exc:
        raise InputFileError(model_file, f"MuJoCo cannot load the model: {exc}") from None
    base = model_file.parent
    spec.compiler.fusestatic = False  # keep every named body (a URDF's fixed links too)
    spec.meshdir = str((base / spec.meshdir).resolve())
    spec.texturedir = str((base / spec.texturedir).resolve())
    if resolve_package_uris(spec, model_file, packages or {}):
        spec.strippath = False  # the resolved files' folders matter
    drop_missing_meshes(spec)
    root = spec.worldbody.first_body()
    if root is None:
        raise InputFileError(model_file, "the model has no body")
    if not any(j.type == mujoco.mjtJoint.mjJNT_FREE for j in root.joints):
        root.add_freejoint(name="root")
    return spec


def drop_missing_meshes(spec: mujoco.MjSpec) -> tuple[str, ...]:
    """Delete the meshes whose file is missing, and every geom that uses one.

    Mesh files are looked up in ``spec.meshdir`` (absolute). Masses given by inertials stay;
    a body whose mass came from a dropped geom loses it.

    Returns:
        The dropped meshes' file names.
    """
    folder = Path(spec.meshdir)
    missing = [m for m in spec.meshes if m.file and not (folder / m.file).is_file()]
    names = {m.name for m in missing}
    for geom in [g for g in spec.geoms if g.type == mujoco.mjtGeom.mjGEOM_MESH]:
        if geom.meshname in names:
            spec.delete(geom)
    files = tuple(str(m.file) for m in missing)
    for mesh in missing:
        spec.delete(mesh)
    return files


YAW_TO_FACE_X_RAD = {"+x": 0.0, "-x": math.pi, "+y": -0.5 * math.pi, "-y": 0.5 * math.pi}
"""The turn about the vertical [rad] that makes a robot facing each model axis face +x."""


def face_world_x(spec: mujoco.MjSpec, forward: str, compiled: mujoco.MjModel) -> None:
    """Turn the root body of ``spec`` about the world's z so the robot faces +x.

    ``forward`` is the root-frame axis the robot faces (a URDF whose root frame faces
    backwards: ``-x``); the root's orientation as compiled (``compiled.body_quat``, whatever
    form the file gave it in) is premultiplied by the yaw :data:`YAW_TO_FACE_X_RAD`.
    """
    root = spec.worldbody.first_body()
    yaw = np.zeros(4)
    mujoco.mju_axisAngle2Quat(yaw, np.array([0.0, 0.0, 1.0]), YAW_TO_FACE_X_RAD[forward])
    turned = np.zeros(4)
    mujoco.mju_mulQuat(turned, yaw, compiled.body_quat[compiled.body(root.name).id])
    root.alt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
    root.quat = turned


def exclude_initial_self_contacts(
    spec: mujoco.MjSpec, model: mujoco.MjModel, data: mujoco.MjData
) -> tuple[tuple[str, str], ...]:
    """Exclude contacts between the robot's bodies whose geoms touch at the initial pose.

    An imported model's links often overlap where they meet (a thigh mesh reaching into the
    pelvis across the small hip links between them: MuJoCo only filters parent and child);
    simulated as they are, such overlaps push the links apart with forces of kilonewtons.
    Geoms touching at the initial pose (``data`` after ``mj_forward``) are taken as meant to
    overlap: their bodies get an ``<exclude>`` (unnamed bodies are named ``zmpkit/body{id}``
    first). Contacts with the world (the floor) are kept.

    Returns:
        The excluded pairs of body names, each sorted, sorted.
    """
    pairs = set()
    for contact in data.contact[: data.ncon]:
        bodies = sorted(int(model.geom_bodyid[g]) for g in (contact.geom1, contact.geom2))
        if bodies[0] != 0 and bodies[0] != bodies[1]:
            pairs.add((bodies[0], bodies[1]))
    names = []
    for pair in sorted(pairs):
        named = []
        for body_id in pair:
            body = spec.body(model.body(body_id).name) if model.body(body_id).name else None
            if body is None:
                body = spec.bodies[body_id]
                body.name = f"{NAMESPACE}body{body_id}"
            named.append(body.name)
        exclude = spec.add_exclude()
        exclude.bodyname1, exclude.bodyname2 = named
        names.append((named[0], named[1]))
    return tuple(sorted((min(a, b), max(a, b)) for a, b in names))


def _compile(robot: RobotFile, spec: mujoco.MjSpec) -> tuple[mujoco.MjModel, mujoco.MjData]:
    try:
        model = spec.compile()
    except ValueError as exc:
        raise InputFileError(robot.model, f"MuJoCo cannot compile the model: {exc}") from None
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _subtree(model: mujoco.MjModel, root: int) -> list[int]:
    inside = [root]
    for body in range(root + 1, model.nbody):
        if int(model.body_parentid[body]) in inside:
            inside.append(body)
    return inside


def geom_corners(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> NDArray[np.float64]:
    """The 8 corners of a geom's bounding box in the world frame [m], shape (8, 3)."""
    centre, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    local = centre + signs * half
    return data.geom_xpos[geom] + local @ data.geom_xmat[geom].reshape(3, 3).T


COLLISION_GROUP = 3
"""The geom group MuJoCo Menagerie puts collision geoms in (visual ones in 1 and 2)."""


def collision_geoms(model: mujoco.MjModel) -> NDArray[np.bool_]:
    """Which geoms are the model's collision geoms, shape (ngeom,).

    Those with a ``contype`` or ``conaffinity``; a model that gives none (its contacts come
    from explicit ``<pair>`` elements of a scene file, as Menagerie's Apollo's do) marks
    them by group instead: :data:`COLLISION_GROUP`, else every geom.
    """
    robot = model.geom_bodyid != 0
    colliding = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
    if np.any(colliding & robot):
        return colliding
    grouped = model.geom_group == COLLISION_GROUP
    return grouped if np.any(grouped & robot) else np.ones(model.ngeom, dtype=bool)


def footprint(robot: RobotFile, model: mujoco.MjModel, data: mujoco.MjData, side: str) -> FootPrint:
    """The sole of ``side``'s foot from its collision geoms at the initial pose.

    Raises:
        InputFileError: on an unknown foot body (listing the model's bodies), or a foot
            without a collision geom.
    """
    body, geoms = _foot_geoms(robot, model, side)
    corners = np.vstack([geom_corners(model, data, g) for g in geoms])
    low, high = corners.min(axis=0), corners.max(axis=0)
    length = robot.sole_length_m or float(high[0] - low[0])
    width = robot.sole_width_m or float(high[1] - low[1])
    centre = (float(0.5 * (low[0] + high[0])), float(0.5 * (low[1] + high[1])))
    return FootPrint(body, centre, float(low[2]), length, width)


def _foot_geoms(robot: RobotFile, model: mujoco.MjModel, side: str) -> tuple[str, list[int]]:
    """``side``'s foot body and the collision geoms of its subtree (at least one)."""
    body = foot_body(robot, model, side)
    bodies = _subtree(model, model.body(body).id)
    colliding = collision_geoms(model)
    geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] in bodies and colliding[g]]
    if not geoms:
        raise InputFileError(robot.path, f"body {body!r} has no collision geom", key=f"feet.{side}")
    return body, geoms


def foot_body(robot: RobotFile, model: mujoco.MjModel, side: str) -> str:
    """The body of ``side``'s foot (a named site's body for ``{site: NAME}``).

    Raises:
        InputFileError: naming the field and listing the valid names.
    """
    kind, name = robot.feet[side]
    names = body_names(model)
    if kind == "site":
        sites = [model.site(s).name for s in range(model.nsite)]
        if name not in sites:
            raise InputFileError(
                robot.path,
                f"unknown site {shorten(name)}; sites: {list_some(sites) or 'none'}",
                key=f"feet.{side}",
            )
        return str(model.body(int(model.site_bodyid[model.site(name).id])).name)
    if name not in names:
        raise InputFileError(
            robot.path,
            f"unknown body {shorten(name)}; bodies: {list_some(names)}",
            key=f"feet.{side}",
        )
    return name


def body_names(model: mujoco.MjModel) -> list[str]:
    """The model's bodies but the world, in tree order."""
    return [model.body(b).name for b in range(1, model.nbody)]


def _hinges(model: mujoco.MjModel) -> list[str]:
    return [
        model.joint(j).name
        for j in range(model.njnt)
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE  # an unnamed free joint is skipped
    ]


def name_problems(robot: RobotFile, model: mujoco.MjModel) -> tuple[InputFileError, ...]:
    """Every body, site and joint the robot file names that the model lacks, one problem each.

    Checks the feet (and that each has a collision geom), the legs' joints (hinges), the IMU
    and torso bodies and the ``walking.posture`` joints (leg joints). A side whose foot or
    leg did not read (:func:`~zmpkit.robots.robot_file.draft_robot_file`) is skipped.

    Returns:
        The problems, each naming the field and listing the valid names (shortened).
    """
    problems = Problems()
    for side in robot.feet:
        problems.attempt(_foot_geoms, robot, model, side)
    hinges = _hinges(model)
    for side, joints in robot.legs.items():
        for name in joints:
            if name not in hinges:
                message = (
                    f"unknown joint {shorten(name)}; hinge joints: {list_some(hinges) or 'none'}"
                )
                problems.add(InputFileError(robot.path, message, key=f"legs.{side}"))
    bodies = body_names(model)
    for field in ("imu", "torso"):
        name = getattr(robot, field)
        if name is not None and name not in bodies:
            message = f"unknown body {shorten(name)}; bodies: {list_some(bodies)}"
            problems.add(InputFileError(robot.path, message, key=field))
    legs = [joint for joints in robot.legs.values() for joint in joints]
    for name in robot.walking.posture_rad or {}:
        if name not in legs:
            message = f"unknown leg joint {shorten(name)}; leg joints: {list_some(legs) or 'none'}"
            problems.add(InputFileError(robot.path, message, key="walking.posture"))
    return problems.found


def check_names(robot: RobotFile, model: mujoco.MjModel) -> None:
    """Every joint and body the robot file names exists (:func:`name_problems`).

    Raises:
        InputFileProblemsError: carrying every unknown name.
    """
    Problems(name_problems(robot, model)).raise_any()


def compile_model(robot: RobotFile) -> mujoco.MjModel:
    """The robot file's model as MuJoCo compiles it (before zmpkit adds anything).

    Raises:
        InputFileError: naming the model file if MuJoCo cannot load or compile it, or the
            packages of its ``package://`` URIs not found.
    """
    return _compile(robot, load_spec(robot.model, robot.packages))[0]


def root_body(model: mujoco.MjModel) -> str:
    """The first body under the world (the floating base)."""
    return str(model.body(1).name)


def _servo(
    robot: RobotFile, model: mujoco.MjModel, data: mujoco.MjData, sole_z: float
) -> IdealServoParams:
    """The ideal servo: the file's gains, else scaled from weight × CoM height [N·m]."""
    height = float(data.subtree_com[0][2]) - sole_z
    weight_moment = float(model.body_subtreemass[0]) * 9.81 * height
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
        face_world_x(spec, robot.forward, _compile(robot, spec)[0])
    model, data = _compile(robot, spec)
    check_names(robot, model)
    excluded = exclude_initial_self_contacts(spec, model, data)
    feet = {side: footprint(robot, model, data, side) for side in SIDES}
    mass = float(model.body_subtreemass[0])
    servo = _servo(robot, model, data, min(f.bottom_z_m for f in feet.values()))
    h = robot.sole_height_m
    for side, foot in feet.items():
        for b in _subtree(model, model.body(foot.body).id):
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
    return UserModel(ET.tostring(xml, encoding="unicode"), feet, mass, servo, excluded)


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
