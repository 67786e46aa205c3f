"""A user's model file (MJCF or URDF) as MuJoCo loads and compiles it, before zmpkit adds to it.

:func:`load_spec` reads the file with MuJoCo's own loader (:class:`mujoco.MjSpec`), resolves
``package://`` mesh URIs, drops geoms whose mesh file is missing and adds a free joint at the
root; :func:`face_world_x` turns the robot to face +x; :func:`exclude_initial_self_contacts`
keeps overlapping links of an imported model from pushing each other apart.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import mujoco
import numpy as np

from zmpkit.errors import InputFileError
from zmpkit.robots.package_uris import resolve_package_uris
from zmpkit.robots.robot_file import RobotFile
from zmpkit.sim.names import NAMESPACE

__all__ = [
    "YAW_TO_FACE_X_RAD",
    "body_names",
    "compile_model",
    "compile_spec",
    "drop_missing_meshes",
    "exclude_initial_self_contacts",
    "face_world_x",
    "load_spec",
    "root_body",
]


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


def compile_spec(robot: RobotFile, spec: mujoco.MjSpec) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """``spec`` compiled, with its data at the initial pose (after ``mj_forward``).

    Raises:
        InputFileError: naming the robot file's model if MuJoCo cannot compile it.
    """
    try:
        model = spec.compile()
    except ValueError as exc:
        raise InputFileError(robot.model, f"MuJoCo cannot compile the model: {exc}") from None
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def compile_model(robot: RobotFile) -> mujoco.MjModel:
    """The robot file's model as MuJoCo compiles it (before zmpkit adds anything).

    Raises:
        InputFileError: naming the model file if MuJoCo cannot load or compile it, or the
            packages of its ``package://`` URIs not found.
    """
    return compile_spec(robot, load_spec(robot.model, robot.packages))[0]


def body_names(model: mujoco.MjModel) -> list[str]:
    """The model's bodies but the world, in tree order."""
    return [model.body(b).name for b in range(1, model.nbody)]


def root_body(model: mujoco.MjModel) -> str:
    """The first body under the world (the floating base)."""
    return str(model.body(1).name)
