"""The walking posture ``robot init`` chooses: torso lean, crouch, and the ZMP's place in the sole.

The test biped's upright crouch keeps every leg joint far from its limits, so it is not
probed and its robot file gets no ``walking:``. A probe in a leaning posture on it solves the
plan (the lean is what the IK holds). The Berkeley Humanoid, whose upright crouch holds its
ankles at their 30° limit, is in the slow tests (test_unseen_humanoids).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from helpers.biped import BIPED_MJCF
from zmpkit.cli import main
from zmpkit.experiments.walking_posture import (
    CROUCH_MARGIN_RAD,
    WalkingPosture,
    candidates,
    choose_walking_posture,
    crouch_margin_rad,
    probe_posture,
)
from zmpkit.robots.registry import get_robot
from zmpkit.robots.robot_file_reader import read_robot_file


@pytest.fixture
def biped_yaml(tmp_path: Path) -> Path:
    model = tmp_path / "biped.xml"
    model.write_text(BIPED_MJCF, encoding="utf-8")
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    return out


def test_a_robot_whose_crouch_is_far_from_its_limits_keeps_the_default(biped_yaml: Path) -> None:
    assert "walking" not in yaml.safe_load(biped_yaml.read_text(encoding="utf-8"))
    robot = get_robot(str(biped_yaml))
    assert crouch_margin_rad(robot) > CROUCH_MARGIN_RAD
    choice = choose_walking_posture(robot, read_robot_file(biped_yaml))
    assert choice.default is None
    assert choice.chosen is None
    assert choice.tried == 0


@pytest.mark.slow
def test_a_leaning_posture_is_what_the_ik_holds(biped_yaml: Path) -> None:
    robot = get_robot(str(biped_yaml))
    file = read_robot_file(biped_yaml)
    probe = probe_posture(robot, file, WalkingPosture(torso_pitch_rad=0.2, zmp_forward_m=0.01))
    assert probe.realisable
    assert probe.comfortable
    upright = probe_posture(robot, file, WalkingPosture())
    assert upright.ik_error_m < 1e-3
    assert probe.least_margin_rad != pytest.approx(upright.least_margin_rad)  # it moved


def test_candidates_go_from_centred_and_upright_to_under_the_ankle_and_leaning() -> None:
    tried = candidates(ankle_forward=-0.031, quarter_sole_m=0.04)
    assert WalkingPosture() not in tried  # the default was probed before
    assert tried[0] == WalkingPosture(0.0, 0.06, 0.0)
    assert [p.zmp_forward_m for p in tried] == [0.0] * 7 + [-0.031] * 8
    pitches = [p.torso_pitch_rad for p in tried if p.zmp_forward_m != 0.0]
    assert np.all(np.diff(pitches) >= 0.0)
    assert {p.zmp_forward_m for p in candidates(-0.2, 0.04)} == {0.0, -0.04}  # clipped
    assert {p.zmp_forward_m for p in candidates(0.0005, 0.04)} == {0.0}  # no second point


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("torso_pitch", 2.0, "walking.torso_pitch: expected a number within ±1 rad, got 2.0"),
        ("zmp_forward", "far", "walking.zmp_forward: expected a number within ±0.2 m"),
    ],
)
def test_bad_walking_posture_keys_get_one_line(
    biped_yaml: Path, capsys: pytest.CaptureFixture[str], key: str, value: object, message: str
) -> None:
    with biped_yaml.open("a", encoding="utf-8") as f:
        f.write(f"walking:\n  {key}: {value!r}\n".replace("'", ""))
    assert main(["robot", "check", str(biped_yaml)]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert len(err.strip().splitlines()) == 1


def test_the_walking_keys_reach_the_walk(biped_yaml: Path) -> None:
    with biped_yaml.open("a", encoding="utf-8") as f:
        f.write("walking:\n  torso_pitch: 0.2\n  zmp_forward: -0.01\n")
    walking = get_robot(str(biped_yaml)).require_walking()
    assert walking.ik_settings.torso_pitch_rad == 0.2
    assert walking.zmp_forward_m == -0.01
