"""The feet of a user's model: which body each is, its collision geoms, its sole at the start.

The sole's size and centre come from the foot's collision geoms at the initial pose (their
bounding boxes), unless the robot file gives the sole's length and width.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit._validate import list_some, shorten
from zmpkit.errors import InputFileError
from zmpkit.robots.robot_file import RobotFile
from zmpkit.robots.user_model_file import body_names

__all__ = [
    "COLLISION_GROUP",
    "FootPrint",
    "collision_geoms",
    "foot_body",
    "foot_geoms",
    "footprint",
    "geom_corners",
    "subtree_bodies",
]


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


def subtree_bodies(model: mujoco.MjModel, root: int) -> list[int]:
    """The body ``root`` and every body below it, by id, in tree order."""
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
    body, geoms = foot_geoms(robot, model, side)
    corners = np.vstack([geom_corners(model, data, g) for g in geoms])
    low, high = corners.min(axis=0), corners.max(axis=0)
    length = robot.sole_length_m or float(high[0] - low[0])
    width = robot.sole_width_m or float(high[1] - low[1])
    centre = (float(0.5 * (low[0] + high[0])), float(0.5 * (low[1] + high[1])))
    return FootPrint(body, centre, float(low[2]), length, width)


def foot_geoms(robot: RobotFile, model: mujoco.MjModel, side: str) -> tuple[str, list[int]]:
    """``side``'s foot body and the collision geoms of its subtree (at least one)."""
    body = foot_body(robot, model, side)
    bodies = subtree_bodies(model, model.body(body).id)
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
