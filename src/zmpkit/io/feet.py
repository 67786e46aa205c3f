"""The FEET.yaml file: where each foot's force–torque sensor sits in the world.

Format (lengths in m, angles in rad)::

    right: {position: [x, y, z], rpy: [roll, pitch, yaw], sole_height: h}
    left:  {position: [x, y, z], rpy: [roll, pitch, yaw], sole_height: h}

``position`` is the sensor origin in the world frame, ``rpy`` the sensor frame's orientation
in the world (R = Rz(yaw)·Ry(pitch)·Rx(roll)), ``sole_height`` the height of the sensor origin
above the sole (the ground plane when the foot is flat).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypedDict

from zmpkit.errors import InputFileError
from zmpkit.io.yaml_file import read_yaml_mapping, require_number, require_vector
from zmpkit.sensors import SensorMount

__all__ = ["FOOT_NAMES", "FootMountEntry", "feet_from_mapping", "read_feet_yaml"]

FOOT_NAMES = ("right", "left")
_FOOT_FIELDS = ("position", "rpy", "sole_height")


class FootMountEntry(TypedDict):
    """One foot's entry of the format above, as the robots' built-in ``*_feet_mounts`` give it."""

    position: list[float]
    rpy: list[float]
    sole_height: float


def read_feet_yaml(path: str | Path) -> dict[str, SensorMount]:
    """Read FEET.yaml into one :class:`~zmpkit.sensors.SensorMount` per foot.

    Raises:
        InputFileError: naming the file and the field that is missing or malformed.
    """
    path = Path(path)
    return feet_from_mapping(read_yaml_mapping(path), source=path)


def feet_from_mapping(
    data: Mapping[str, Any], source: str | Path = "<feet>"
) -> dict[str, SensorMount]:
    """Build the sensor mounts of both feet from an already-parsed mapping."""
    source = Path(source)
    unknown = sorted(set(data) - set(FOOT_NAMES))
    if unknown:
        raise InputFileError(source, f"unknown foot {unknown[0]!r}; valid feet: right, left")
    return {name: _foot(source, name, data.get(name)) for name in FOOT_NAMES}


def _foot(source: Path, name: str, entry: object) -> SensorMount:
    if entry is None:
        raise InputFileError(source, f"missing foot '{name}'; expected keys: right, left")
    if not isinstance(entry, Mapping):
        raise InputFileError(
            source, f"foot '{name}' must be a mapping with keys {', '.join(_FOOT_FIELDS)}"
        )
    for key in _FOOT_FIELDS:
        if key not in entry:
            raise InputFileError(source, f"foot '{name}' is missing field '{key}'")
    extra = sorted(set(entry) - set(_FOOT_FIELDS))
    if extra:
        raise InputFileError(
            source,
            f"foot '{name}' has unknown field '{extra[0]}'; valid: {', '.join(_FOOT_FIELDS)}",
        )
    sole_height = require_number(source, f"{name}.sole_height", entry["sole_height"])
    if sole_height < 0.0:
        raise InputFileError(
            source, f"field '{name}.sole_height' must be >= 0 m, got {sole_height}"
        )
    return SensorMount.from_rpy(
        position=require_vector(source, f"{name}.position", entry["position"], 3),
        rpy=require_vector(source, f"{name}.rpy", entry["rpy"], 3),
        sole_height=sole_height,
        name=name,
    )
