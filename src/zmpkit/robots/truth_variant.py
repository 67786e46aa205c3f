"""Another robot than the shipped one: a truth file with one parameter scaled.

Held-out validation needs robots a method was not tuned on — "the same robot with 30 % stiffer
gears" — without the pipeline ever reading a truth value: it asks for a variant by the
parameter's path in the truth file and a factor, and hands the file to the simulator.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import yaml

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.robots.robot import Robot

__all__ = ["scaled_truth_file"]


def _scaled(node: Any, path: Sequence[str], factor: float, name: str) -> Any:
    """``node`` with the number (or every number of the list) at ``path`` times ``factor``."""
    if not path:
        if isinstance(node, bool) or not isinstance(node, int | float | list):
            raise ParameterError(f"truth value {name} is not a number; cannot scale it")
        if isinstance(node, list):
            return [_scaled(v, (), factor, name) for v in node]
        return float(node) * factor
    if not isinstance(node, dict) or path[0] not in node:
        valid = ", ".join(sorted(node)) if isinstance(node, dict) else "none"
        raise ParameterError(f"the truth file has no {name}; at {path[0]!r} it has: {valid}")
    return {**node, path[0]: _scaled(node[path[0]], path[1:], factor, name)}


def scaled_truth_file(robot: Robot, parameter: str, factor: float, folder: Path) -> Path:
    """Write the robot's shipped truth with ``parameter`` (dotted path) times ``factor``.

    Args:
        robot: the robot whose shipped truth file is varied.
        parameter: the value's path in the truth file, e.g. ``gear.stiffness``.
        factor: the scale [-], > 0.
        folder: where the file goes (created); its name says the variation.

    Returns:
        The variant's path, ``{robot}_{parameter}_x{factor}_{hash}.yaml``; the simulator
        loads it like any truth file.
    """
    _validate.positive("factor", factor)
    source = robot.truth.default_path
    document = yaml.safe_load(source.read_text(encoding="utf-8"))
    varied = _scaled(document, parameter.split("."), factor, parameter)
    text = yaml.safe_dump(varied, sort_keys=False)
    digest = hashlib.sha1(text.encode()).hexdigest()[:8]
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{robot.name}_{parameter.replace('.', '_')}_x{factor:g}_{digest}.yaml"
    path.write_text(
        f"# {source.name} of {robot.title} with {parameter} x{factor:g} (zmpkit)\n" + text,
        encoding="utf-8",
    )
    return path
