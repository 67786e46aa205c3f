"""A first ``robot.yaml`` written from a model: feet from the lowest bodies, legs from chains.

:func:`guess_robot_file` loads the MJCF or URDF with MuJoCo (free joint added at the root),
poses it at its initial configuration and guesses:

- **feet**: the two lowest bodies (by their collision geoms' lowest point) on different
  branches of the tree;
- **forward**: the horizontal axis of the feet's length (their collision geoms' extent), in
  the direction the model's left/right names say, else the one its knees bend towards,
  else the one the feet reach further ahead of their ankles (the foot bodies' origins) than
  behind — toes are longer than heels (:mod:`~zmpkit.robots.facing`); sure when no evidence
  disagrees and a strong one is cast (names, knees, or toes on feet at least 1.2 times as
  long as wide whose reach differs by at least 5 % of their length), else said to be a guess;
- **left**: the foot on the left of forward (z × forward);
- **legs**: the hinge joints on the path from each foot up to the first body both feet
  hang from (a waist joint above both hips belongs to neither leg), hip to ankle;
- **imu** and **torso**: the root body.

Each guess comes with the evidence it rests on (:class:`RobotGuess`), printed by
``zmpkit robot init`` and written as comments into the file; the user checks and edits the
result (``zmpkit robot check``).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import yaml

from zmpkit.errors import InputFileError
from zmpkit.robots.facing import FacingVote, decide, facing_votes, path_to_root
from zmpkit.robots.user_feet import collision_geoms, geom_corners
from zmpkit.robots.user_model_file import load_spec

__all__ = [
    "RobotGuess",
    "append_walking_keys",
    "guess_robot",
    "guess_robot_file",
    "write_robot_file",
]

FORWARD_SURE_ASPECT = 1.2
"""Feet at least this many times as long as wide show their long axis [-]."""
FORWARD_SURE_REACH = 0.05
"""Toes reaching this share of the foot's length further than the heel show forward [-]."""


@dataclass(frozen=True)
class RobotGuess:
    """A first ``robot.yaml`` document and what each guess rests on.

    Attributes:
        doc: the document (``name``, ``model``, ``feet``, ``legs``, ``forward``, ``imu``,
            ``torso``; ``packages`` when given).
        notes: one line per guess: what was guessed, from what, and how sure.
        sure: False when a guess is weak (the notes say which) and must be checked by hand.
    """

    doc: dict
    notes: tuple[str, ...]
    sure: bool


def _lowest_z(model: mujoco.MjModel, data: mujoco.MjData) -> dict[int, float]:
    """Each body's lowest collision-geom point at the initial pose [m] (bodies with geoms).

    Collision geoms as :func:`~zmpkit.robots.user_feet.collision_geoms` finds them.
    """
    low: dict[int, float] = {}
    colliding = collision_geoms(model)
    for g in range(model.ngeom):
        body = int(model.geom_bodyid[g])
        if body == 0 or not colliding[g]:
            continue
        z = float(geom_corners(model, data, g)[:, 2].min())
        low[body] = min(low.get(body, np.inf), z)
    return low


def _separate(model: mujoco.MjModel, a: int, b: int) -> bool:
    """Whether neither body is an ancestor of the other."""
    return a not in path_to_root(model, b) and b not in path_to_root(model, a)


def _leg_paths(model: mujoco.MjModel, right: int, left: int) -> dict[str, list[int]]:
    """Each foot's bodies below the last body both feet hang from, hip first."""
    paths = {"right": path_to_root(model, right), "left": path_to_root(model, left)}
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


def _foot_geoms(model: mujoco.MjModel, foot: int) -> list[int]:
    colliding = collision_geoms(model)
    return [g for g in range(model.ngeom) if int(model.geom_bodyid[g]) == foot and colliding[g]]


def _forward(model: mujoco.MjModel, data: mujoco.MjData, feet: list[int]) -> tuple[str, str, bool]:
    """The model axis the robot faces, the evidence, and whether it is sure (module docstring)."""
    extent = np.zeros(2)
    reach = np.zeros(2)  # (ahead − behind) of the ankle, summed over the feet [m]
    for foot in feet:
        corners = np.vstack([geom_corners(model, data, g) for g in _foot_geoms(model, foot)])
        low, high = corners[:, :2].min(axis=0), corners[:, :2].max(axis=0)
        ankle = data.xpos[foot][:2]
        extent += high - low
        reach += (high - ankle) - (ankle - low)
    axis = 0 if extent[0] >= extent[1] else 1
    length, width = extent[axis] / 2.0, extent[1 - axis] / 2.0
    share = abs(reach[axis]) / 2.0 / length if length > 0.0 else 0.0
    toe_sign = 1 if reach[axis] >= 0.0 else -1
    toes = FacingVote(
        "toes",
        toe_sign,
        width > 0.0 and length >= FORWARD_SURE_ASPECT * width and share >= FORWARD_SURE_REACH,
        f"the feet are {length:.3f} m long along {'xy'[axis]} ({width:.3f} m wide) and reach "
        f"{abs(reach[axis]) / 2.0:.3f} m further towards {'+' if toe_sign > 0 else '-'}"
        f"{'xy'[axis]} of their ankles than away",
    )
    votes = facing_votes(model, data, feet, axis, toes)
    sign, sure = decide(votes)
    label = f"{'+' if sign > 0 else '-'}{'xy'[axis]}"
    disagree = [v.source for v in votes if v.sign not in (0, sign)]
    evidence = "; ".join(f"{v.source}: {v.evidence}" for v in votes)
    if disagree:
        evidence += f" (the {' and '.join(disagree)} disagree)"
    return label, evidence, sure


def guess_robot(
    model_path: str | Path, out: str | Path, packages: Mapping[str, Path] | None = None
) -> RobotGuess:
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
    forward, evidence, sure = _forward(model, data, feet)
    unit = {"+x": (1.0, 0.0), "-x": (-1.0, 0.0), "+y": (0.0, 1.0), "-y": (0.0, -1.0)}[forward]
    leftward = np.array([-unit[1], unit[0]])  # z × forward
    left, right = sorted(feet, key=lambda b: -float(data.xpos[b][:2] @ leftward))
    root = int(path_to_root(model, left)[0])
    paths = _leg_paths(model, right, left)
    legs = {side: _hinges(model, path) for side, path in paths.items()}
    folder = Path(out).resolve().parent
    doc: dict = {"name": model_file.stem, "model": os.path.relpath(model_file, folder)}
    if given:
        doc["packages"] = {name: os.path.relpath(p, folder) for name, p in given.items()}
    names = {"right": model.body(right).name, "left": model.body(left).name}
    hang = model.body(int(model.body_parentid[paths["left"][0]])).name if paths["left"] else "?"
    notes = (
        f"feet: {names['right']} (right) and {names['left']} (left): the two lowest bodies on "
        "separate branches, left of forward",
        f"forward: {forward} in the model's frame: {evidence}"
        + ("" if sure else "; a weak guess: check `forward:` by hand"),
        f"legs: {len(legs['right'])} and {len(legs['left'])} joints, from "
        f"{legs['right'][0] if legs['right'] else '-'} and "
        f"{legs['left'][0] if legs['left'] else '-'}, below {hang} (both feet hang from it)",
        f"imu and torso: {model.body(root).name} (the root body)",
    )
    document = {
        **doc,
        "feet": names,
        "legs": legs,
        "forward": forward,
        "imu": model.body(root).name,
        "torso": model.body(root).name,
    }
    return RobotGuess(document, notes, sure)


def guess_robot_file(
    model_path: str | Path, out: str | Path, packages: Mapping[str, Path] | None = None
) -> dict:
    """The document of :func:`guess_robot` (its notes dropped)."""
    return guess_robot(model_path, out, packages).doc


def write_robot_file(
    model_path: str | Path, out: str | Path, packages: Mapping[str, Path] | None = None
) -> RobotGuess:
    """Write :func:`guess_robot`'s document to ``out``, its notes as the header comment."""
    guess = guess_robot(model_path, out, packages)
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    header = (
        "# robot.yaml written by `zmpkit robot init` from the model: check the feet, the\n"
        "# legs (hip to ankle) and forward, then run `zmpkit robot check` on this file.\n"
        + "".join(f"# guessed {note}\n" for note in guess.notes)
    )
    path.write_text(header + yaml.safe_dump(guess.doc, sort_keys=False), encoding="utf-8")
    return guess


def append_walking_keys(out: str | Path, keys: Mapping[str, float], note: str) -> None:
    """Add a ``walking:`` section with ``keys`` to the robot file ``out``, ``note`` above it.

    Args:
        out: a robot file :func:`write_robot_file` wrote (it has no ``walking:`` yet).
        keys: ``walking:`` key → value (``torso_pitch`` [rad], ``crouch`` [-],
            ``zmp_forward`` [m]).
        note: why, one line (written as a comment).
    """
    path = Path(out)
    lines = [f"# guessed walking posture: {note}", "walking:"]
    lines += [f"  {key}: {value:.4g}" for key, value in keys.items()]
    with path.open("a", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
