"""A model whose root frame faces another way: ``robot init`` finds ``forward:``, zmpkit
turns the robot to face +x, and ``robot check`` catches a wrong guess.

The test biped is turned half a turn about the vertical in its own file (a URDF exported
facing backwards is the case met in the wild): its toes point to −x and its left leg lies
at −y of the model frame.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml

from helpers.biped import BIPED_MJCF
from zmpkit.cli import main
from zmpkit.robots.registry import get_robot
from zmpkit.sim.names import sole_site

ROOT = '<body name="pelvis" pos="0 0 0.55">'


def _turned(tmp_path: Path, yaw_rad: float) -> Path:
    model = tmp_path / "turned.xml"
    model.write_text(
        BIPED_MJCF.replace(ROOT, f'<body name="pelvis" pos="0 0 0.55" euler="0 0 {yaw_rad!r}">'),
        encoding="utf-8",
    )
    return model


@pytest.mark.parametrize(("yaw_rad", "forward"), [(math.pi, "-x"), (0.5 * math.pi, "+y")])
def test_init_finds_forward_and_the_robot_faces_x(
    tmp_path: Path, yaw_rad: float, forward: str, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(_turned(tmp_path, yaw_rad)), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"guessed forward: {forward} in the model's frame: the feet are 0.140 m long" in printed
    assert "weak guess" not in printed
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["forward"] == forward
    assert doc["feet"] == {"right": "r_foot", "left": "l_foot"}  # not swapped
    assert main(["robot", "check", str(out)]) == 0
    assert "to the left of the right foot, facing +x: OK" in capsys.readouterr().out
    sim = get_robot(str(out)).make_simulation("none")
    soles = {side: sim.data.site(sole_site(side)).xpos for side in ("left", "right")}
    assert soles["left"][1] - soles["right"][1] == pytest.approx(0.12, abs=1e-6)


def test_a_turned_robot_walks_forward(tmp_path: Path) -> None:
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(_turned(tmp_path, math.pi)), "--out", str(out)]) == 0
    walk = tmp_path / "walk"
    args = ["walk", "--robot", str(out), "--controller", "open", "--duration", "4"]
    assert main([*args, "--out", str(walk)]) == 0
    summary = json.loads((walk / "summary.json").read_text(encoding="utf-8"))
    assert not summary["fell"]
    assert summary["mean_speed_mps"] == pytest.approx(0.2, rel=0.1)  # along world +x


def test_a_wrong_forward_fails_the_check_and_every_command(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(_turned(tmp_path, math.pi)), "--out", str(out)]) == 0
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text(out.read_text(encoding="utf-8").replace("forward: -x", "forward: +x"))
    capsys.readouterr()
    assert main(["robot", "check", str(wrong)]) == 1
    assert "to the RIGHT of the right foot, facing +x: MISMATCH" in capsys.readouterr().out
    assert main(["walk", "--robot", str(wrong), "--out", str(tmp_path / "w")]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "its left foot stands 120.0 mm right of its right foot" in line


def test_a_bad_forward_names_the_valid_axes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(_turned(tmp_path, 0.0)), "--out", str(out)]) == 0
    out.write_text(out.read_text(encoding="utf-8").replace("forward: +x", "forward: ahead"))
    capsys.readouterr()
    assert main(["robot", "check", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "forward: expected one of +x, -x, +y, -y, got 'ahead'" in line
