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
    guessed = f"guessed forward: {forward} in the model's frame: names: l_foot is named left"
    assert guessed in printed
    # the foot's origin swung 0.5 rad about the knee, 0.22 m above it: 0.22 sin 0.5 = 0.105 m
    assert "knees: flexing r_knee and l_knee carries the feet 0.105 m towards" in printed
    assert "toes: the feet are 0.140 m long" in printed
    assert "disagree" not in printed
    assert "weak guess" not in printed
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["forward"] == forward
    assert doc["feet"] == {"right": "r_foot", "left": "l_foot"}  # not swapped
    assert main(["robot", "check", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "to the left of the right foot, facing +x: OK" in printed
    sim = get_robot(str(out)).make_simulation("none")
    below_knee_m = sim.data.joint("l_knee").xanchor[2] - sim.data.site(sole_site("left")).xpos[2]
    shift_mm = 1e3 * below_knee_m * math.sin(0.5)  # the sole's body swung 0.5 rad about the knee
    assert f"flexing r_knee and l_knee carries the feet {shift_mm:.0f} mm backwards" in printed
    soles = {side: sim.data.site(sole_site(side)).xpos for side in ("left", "right")}
    assert soles["left"][1] - soles["right"][1] == pytest.approx(0.12, abs=1e-6)


@pytest.mark.slow
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


def _nameless(model: Path) -> Path:
    """The model with no left/right in its names: l_ → a_, r_ → b_."""
    text = model.read_text(encoding="utf-8").replace('"l_', '"a_').replace('"r_', '"b_')
    text = text.replace("'l_", "'a_").replace("'r_", "'b_")
    model.write_text(text, encoding="utf-8")
    return model


def test_without_left_and_right_names_the_knees_show_forward(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    model = _nameless(_turned(tmp_path, math.pi))
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "names: the feet's names do not say left and right" in printed
    assert "guessed forward: -x" in printed
    assert "weak guess" not in printed
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["feet"] == {"right": "b_foot", "left": "a_foot"}


def test_a_wrong_forward_with_consistent_feet_fails_on_the_knees(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The guess a backwards URDF once got: forward flipped *and* the feet swapped to match,
    so the feet stand on their sides; only the knees, bending the wrong way, show it."""
    model = _nameless(_turned(tmp_path, math.pi))
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    doc["forward"] = "+x"
    doc["feet"] = {"right": doc["feet"]["left"], "left": doc["feet"]["right"]}
    doc["legs"] = {"right": doc["legs"]["left"], "left": doc["legs"]["right"]}
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text(yaml.safe_dump(doc), encoding="utf-8")
    capsys.readouterr()
    assert main(["robot", "check", str(wrong)]) == 1
    printed = capsys.readouterr().out
    assert "to the left of the right foot, facing +x: OK" in printed
    assert "132 mm FORWARDS, facing +x: MISMATCH" in printed  # as the test above derives
    assert main(["walk", "--robot", str(wrong), "--out", str(tmp_path / "w")]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "flexing its knees carries its feet 132 mm forwards (a wrong forward:)" in line
