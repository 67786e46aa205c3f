"""``package://`` URIs of a URDF's meshes, resolved against the robot's package folders.

A ROS URDF names its meshes ``package://NAME/path/in/package.stl``. zmpkit rewrites each such
file to ``DIR/path/in/package.stl``, ``DIR`` the folder ``packages:`` of the robot file gives
for ``NAME`` (``zmpkit robot init --package NAME=DIR``), else the nearest folder named ``NAME``
above the model file (the usual ``NAME/urdf/robot.urdf`` layout). A package found in neither
is one :class:`~zmpkit.errors.InputFileError` line naming it and the remedy; every such
package is named (one line each, with the first file that names it) before the error is
raised.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import mujoco

from zmpkit.errors import InputFileError
from zmpkit.robots.problems import Problems

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
        InputFileError: on a package neither given nor above the model file; with several,
            an :class:`~zmpkit.errors.InputFileProblemsError` naming each once.
    """
    used, unknown = set(), set()
    problems = Problems()
    for asset in (*spec.meshes, *spec.textures):
        if not str(asset.file).startswith(PACKAGE_SCHEME):
            continue
        name, _, rest = str(asset.file)[len(PACKAGE_SCHEME) :].partition("/")
        folder = package_folder(name, model_file, packages)
        if folder is None:
            if name not in unknown:
                problems.add(_unknown_package(model_file, str(asset.file), name, packages))
            unknown.add(name)
            continue
        asset.file = str(folder / rest)
        used.add(name)
    problems.raise_any()
    return tuple(sorted(used))


def _unknown_package(
    model_file: Path, uri: str, name: str, packages: Mapping[str, Path]
) -> InputFileError:
    given = ", ".join(sorted(packages)) or "none"
    return InputFileError(
        model_file,
        f"{uri}: unknown package {name!r} (packages given: {given}); give its folder as "
        f"packages: {{{name}: DIR}} in robot.yaml or robot init --package {name}=DIR",
    )
