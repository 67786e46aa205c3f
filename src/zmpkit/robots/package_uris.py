"""``package://`` URIs of a URDF's meshes, resolved against the robot's package folders.

A ROS URDF names its meshes ``package://NAME/path/in/package.stl``. zmpkit rewrites each such
file to ``DIR/path/in/package.stl``, ``DIR`` the folder ``packages:`` of the robot file gives
for ``NAME`` (``zmpkit robot init --package NAME=DIR``), else the nearest folder named ``NAME``
above the model file (the usual ``NAME/urdf/robot.urdf`` layout). A package found in neither
is one :class:`~zmpkit.errors.InputFileError` naming it and the remedy.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import mujoco

from zmpkit.errors import InputFileError

__all__ = ["PACKAGE_SCHEME", "package_folder", "resolve_package_uris"]

PACKAGE_SCHEME = "package://"
"""How a URDF names a file inside a ROS package."""


def package_folder(name: str, model_file: Path, packages: Mapping[str, Path]) -> Path | None:
    """The folder of package ``name``: the one given, else the nearest ancestor so named."""
    if name in packages:
        return packages[name]
    return next((p for p in model_file.resolve().parents if p.name == name), None)


def resolve_package_uris(
    spec: mujoco.MjSpec, model_file: Path, packages: Mapping[str, Path]
) -> tuple[str, ...]:
    """Rewrite every mesh and texture file ``package://NAME/REST`` to an absolute path.

    Args:
        spec: the loaded model, changed in place.
        model_file: the MJCF or URDF file (its ancestors are searched).
        packages: package name → folder (absolute).

    Returns:
        The packages used, sorted.

    Raises:
        InputFileError: on a package neither given nor above the model file.
    """
    used = set()
    for asset in (*spec.meshes, *spec.textures):
        if not str(asset.file).startswith(PACKAGE_SCHEME):
            continue
        name, _, rest = str(asset.file)[len(PACKAGE_SCHEME) :].partition("/")
        folder = package_folder(name, model_file, packages)
        if folder is None:
            given = ", ".join(sorted(packages)) or "none"
            raise InputFileError(
                model_file,
                f"{asset.file}: unknown package {name!r} (packages given: {given}); give its "
                f"folder as packages: {{{name}: DIR}} in robot.yaml or robot init "
                f"--package {name}=DIR",
            )
        asset.file = str(folder / rest)
        used.add(name)
    return tuple(sorted(used))
