"""A first ``robot.yaml`` written from a model: feet from the lowest bodies, legs from chains.

:func:`guess_robot_file` loads the MJCF or URDF with MuJoCo (free joint added at the root),
poses it at its initial configuration and guesses:

- **feet**: the two lowest bodies (by their collision geoms' lowest point) on different
  branches of the tree, the one with the larger y being the left foot;
- **legs**: the hinge joints on the path from each foot up to the first body both feet
  hang from (a waist joint above both hips belongs to neither leg), hip to ankle;
- **imu** and **torso**: the root body.

The user checks and edits the result (``zmpkit robot check``).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

import mujoco
import numpy as np
import yaml

from zmpkit.errors import InputFileError
from zmpkit.robots.user_model import geom_corners, load_spec

__all__ = ["guess_robot_file", "write_robot_file"]


def _lowest_z(model: mujoco.MjModel, data: mujoco.MjData) -> dict[int, float]:
    """Each body's lowest collision-geom point at the initial pose [m] (bodies with geoms)."""
    low: dict[int, float] = {}
    for g in range(model.ngeom):
        body = int(model.geom_bodyid[g])
        if body == 0 or not (model.geom_contype[g] or model.geom_conaffinity[g]):
            continue
        z = float(geom_corners(model, data, g)[:, 2].min())
        low[body] = min(low.get(body, np.inf), z)
    return low


def _path_to_root(model: mujoco.MjModel, body: int) -> list[int]:
    path = [body]
    while int(model.body_parentid[path[-1]]) != 0:
        path.append(int(model.body_parentid[path[-1]]))
    return path[::-1]


def _separate(model: mujoco.MjModel, a: int, b: int) -> bool:
    """Whether neither body is an ancestor of the other."""
    return a not in _path_to_root(model, b) and b not in _path_to_root(model, a)


def _leg_paths(model: mujoco.MjModel, right: int, left: int) -> dict[str, list[int]]:
    """Each foot's bodies below the last body both feet hang from, hip first."""
    paths = {"right": _path_to_root(model, right), "left": _path_to_root(model, left)}
    shared = 0
    for a, b in zip(paths["right"], paths["left"], strict=False):
        if a != b:
            break
        shared += 1
    return {side: path[shared:] for side, path in paths.items()}


def _hinges(model: mujoco.MjModel, bodies: list[int]) -> list[str]:
    return [
        model.joint(j).name
        for b in bodies
        for j in range(model.body_jntadr[b], model.body_jntadr[b] + model.body_jntnum[b])
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE
    ]


def guess_robot_file(
    model_path: str | Path, out: str | Path, packages: Mapping[str, Path] | None = None
) -> dict:
    """A ``robot.yaml`` document for the model at ``model_path``, to be written at ``out``.

    ``packages`` (package name → folder) resolve the model's ``package://`` URIs and are
    written to the document, relative to ``out``'s folder.

    Raises:
        InputFileError: if MuJoCo cannot load the model or no two feet are found.
    """
    model_file = Path(model_path).resolve()
    if not model_file.is_file():
        raise InputFileError(model_file, "no such model file (expected an MJCF .xml or a .urdf)")
    given = {name: Path(folder).resolve() for name, folder in (packages or {}).items()}
    model = load_spec(model_file, given).compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    low = _lowest_z(model, data)
    order = sorted(low, key=lambda b: low[b])
    feet: list[int] = []
    for body in order:
        if all(_separate(model, body, f) for f in feet):
            feet.append(body)
        if len(feet) == 2:
            break
    if len(feet) < 2:
        raise InputFileError(model_file, "found fewer than two separate lowest bodies (feet)")
    left, right = sorted(feet, key=lambda b: -float(data.xpos[b][1]))
    root = int(_path_to_root(model, left)[0])
    legs = {side: _hinges(model, path) for side, path in _leg_paths(model, right, left).items()}
    folder = Path(out).resolve().parent
    doc: dict = {"name": model_file.stem, "model": os.path.relpath(model_file, folder)}
    if given:
        doc["packages"] = {name: os.path.relpath(p, folder) for name, p in given.items()}
    return {
        **doc,
        "feet": {"right": model.body(right).name, "left": model.body(left).name},
        "legs": legs,
        "imu": model.body(root).name,
        "torso": model.body(root).name,
    }


def write_robot_file(
    model_path: str | Path, out: str | Path, packages: Mapping[str, Path] | None = None
) -> Path:
    """Write :func:`guess_robot_file`'s document to ``out`` with a header comment."""
    doc = guess_robot_file(model_path, out, packages)
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    header = (
        "# robot.yaml written by `zmpkit robot init` from the model: check the feet and the\n"
        "# legs (hip to ankle), then run `zmpkit robot check` on this file.\n"
    )
    path.write_text(header + yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path
