"""A URDF whose feet are meshes named by ``package://`` URIs: found above the model file (the
ROS layout) or in the folder ``robot init --package`` / ``packages:`` gives; else one line
naming the package and the remedy."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
import yaml

from helpers.biped import BIPED_URDF
from zmpkit.cli import main
from zmpkit.errors import InputFileError
from zmpkit.robots.registry import get_robot

FOOT_M = (0.14, 0.08, 0.02)
"""The biped's foot box [m], here a mesh."""
URI = "package://biped_description/meshes/foot.stl"


def _box_stl(path: Path, size: tuple[float, float, float]) -> None:
    """A binary STL of a box of ``size`` [m] centred on the origin."""
    corners = (np.array([[i >> 0 & 1, i >> 1 & 1, i >> 2 & 1] for i in range(8)]) - 0.5) * size
    faces = ((0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
             (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5))  # fmt: skip
    path.parent.mkdir(parents=True, exist_ok=True)
    data = bytearray(80) + struct.pack("<I", len(faces))
    for face in faces:
        data += struct.pack("<3f", 0.0, 0.0, 0.0)
        for corner in face:
            data += struct.pack("<3f", *corners[corner])
        data += b"\0\0"
    path.write_bytes(bytes(data))


def _urdf(path: Path) -> Path:
    box = '<box size="{:g} {:g} {:g}"/>'.format(*FOOT_M)
    assert BIPED_URDF.count(box) == 2
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(BIPED_URDF.replace(box, f'<mesh filename="{URI}"/>'), encoding="utf-8")
    return path


def _sole_size(robot_yaml: Path) -> tuple[float, float]:
    return get_robot(robot_yaml).require_walking().sole_size_m


def test_a_package_above_the_urdf_is_found(tmp_path: Path) -> None:
    package = tmp_path / "biped_description"
    _box_stl(package / "meshes" / "foot.stl", FOOT_M)
    model = _urdf(package / "urdf" / "biped.urdf")
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    assert "packages" not in yaml.safe_load(out.read_text(encoding="utf-8"))
    assert _sole_size(out) == pytest.approx(FOOT_M[:2], abs=1e-6)  # the feet's meshes
    assert main(["robot", "check", str(out)]) == 0


def test_a_package_elsewhere_is_given_and_written_to_the_robot_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _box_stl(tmp_path / "ros" / "biped_description" / "meshes" / "foot.stl", FOOT_M)
    model = _urdf(tmp_path / "models" / "biped.urdf")
    out = tmp_path / "robots" / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 2
    assert (
        f"{URI}: unknown package 'biped_description' (packages given: none); give its folder "
        "as packages: {biped_description: DIR} in robot.yaml or robot init --package "
        "biped_description=DIR"
    ) in capsys.readouterr().err
    given = f"biped_description={tmp_path / 'ros' / 'biped_description'}"
    assert main(["robot", "init", str(model), "--out", str(out), "--package", given]) == 0
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["packages"] == {"biped_description": "../ros/biped_description"}
    assert _sole_size(out) == pytest.approx(FOOT_M[:2], abs=1e-6)


def test_a_missing_package_folder_is_named(tmp_path: Path) -> None:
    model = _urdf(tmp_path / "biped.urdf")
    out = tmp_path / "robot.yaml"
    out.write_text(
        f"model: {model.name}\npackages: {{biped_description: nowhere}}\n"
        "feet: {right: r_foot, left: l_foot}\n"
        "legs: {right: [r_hip_roll], left: [l_hip_roll]}\n",
        encoding="utf-8",
    )
    with pytest.raises(InputFileError, match=r"packages\.biped_description: no such folder"):
        get_robot(out)


def test_the_readme_robot_file_is_complete_and_reads(tmp_path: Path) -> None:
    """The README's "complete robot.yaml" gives every field and walking key, and reads (its
    model the test biped, its truth and package folder present)."""
    from helpers.biped import BIPED_MJCF
    from zmpkit.robots.robot_file import FIELDS, WALKING_FIELDS
    from zmpkit.robots.robot_file_reader import read_robot_file

    readme = Path(__file__).parents[2] / "README.md"
    section = readme.read_text(encoding="utf-8").split("A complete `robot.yaml`", 1)[1]
    text = section.split("```yaml\n", 1)[1].split("```", 1)[0]
    doc = yaml.safe_load(text)
    assert tuple(doc) == FIELDS
    assert tuple(doc["walking"]) == WALKING_FIELDS
    folder = tmp_path / "robot"
    folder.mkdir()
    (folder / doc["model"]).write_text(BIPED_MJCF, encoding="utf-8")
    (folder / doc["truth"]).write_text("{}\n", encoding="utf-8")
    for package in doc["packages"].values():
        (folder / package).mkdir(parents=True, exist_ok=True)
    (folder / "robot.yaml").write_text(text, encoding="utf-8")
    robot = read_robot_file(folder / "robot.yaml")
    assert robot.walking.speed_mps == doc["walking"]["speed"]
    assert set(robot.packages) == set(doc["packages"])
