"""A user's own biped, MJCF and URDF: robot init, robot check, a balance sweep and a walk.

The models are built here, in a temporary folder: a 8.4 kg biped with hip roll and pitch,
knee, ankle pitch and roll on each leg, written once as MJCF and once as URDF.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from helpers.biped import BIPED_MJCF, BIPED_URDF, LEG_M
from zmpkit.cli import main
from zmpkit.robots.registry import get_robot


@pytest.fixture(params=["mjcf", "urdf"])
def robot_yaml(request: pytest.FixtureRequest, tmp_path: Path) -> Path:
    """``robot init`` on the biped's model; the written robot.yaml."""
    model = tmp_path / ("biped.xml" if request.param == "mjcf" else "biped.urdf")
    model.write_text(BIPED_MJCF if request.param == "mjcf" else BIPED_URDF, encoding="utf-8")
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    return out


def test_the_walking_defaults_and_balance_model_come_from_the_model(robot_yaml: Path) -> None:
    robot = get_robot(robot_yaml)
    walking, balance = robot.require_walking(), robot.require_balance()
    leg = 2 * LEG_M + 0.05 + 0.005  # hip above the sole plate's bottom [m]
    assert walking.foot_separation_m == pytest.approx(0.12, abs=1e-9)
    assert walking.max_step_length_m == pytest.approx(0.4 * leg, abs=2e-3)
    assert walking.sole_size_m == pytest.approx((0.14, 0.08), abs=1e-6)
    posture = walking.ik_settings.posture_rad
    assert posture["r_knee"] > 0.5  # a crouch: knees bent the human way
    assert posture["r_hip_pitch"] < 0.0
    assert posture["r_ankle_pitch"] < 0.0
    assert walking.series_joints[:3] == ("l_hip_pitch", "l_knee", "l_ankle_pitch")
    standing = balance.com_height_m
    assert walking.com_height_m == pytest.approx(standing - 0.08 * leg, abs=2e-3)
    assert balance.lean_joints["sagittal"] == ("r_ankle_pitch", "l_ankle_pitch")
    assert balance.hip_roll_joints == ("r_hip_roll", "l_hip_roll")
    assert balance.support_polygon_m["frontal"] == pytest.approx((-0.1, 0.1), abs=1e-6)


def test_init_check_balance_sweep_and_walk(
    robot_yaml: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["robot", "check", str(robot_yaml)]) == 0
    assert "F-T vs contact" in capsys.readouterr().out
    push = tmp_path / "push"
    args = ["--robot", str(robot_yaml), "--targets", "0,0.02,0.04", "--hold", "3"]
    assert main(["sim", "push", *args, "--out", str(push), "--workers", "1"]) == 0
    with (push / "steady_state.csv").open(encoding="utf-8") as f:
        rows = {float(r["zmp_ref"]): r for r in csv.DictReader(f)}
    for target in (0.02, 0.04):  # the static ZMP reaches the target within 5 %
        assert float(rows[target]["zmp_measured"]) == pytest.approx(target, rel=0.05)
    walk = tmp_path / "walk"
    args = ["--robot", str(robot_yaml), "--controller", "open", "--duration", "3"]
    assert main(["walk", *args, "--out", str(walk)]) == 0
    summary = json.loads((walk / "summary.json").read_text(encoding="utf-8"))
    assert not summary["fell"]
    assert summary["mean_speed_mps"] == pytest.approx(0.2, rel=0.15)


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["zmpip", "dcm"])
def test_the_feedback_walks_stand_on_a_users_robot(
    robot_yaml: Path, tmp_path: Path, controller: str
) -> None:
    """6 s with feedback on the generated biped (a robot the controllers were not tuned on)."""
    walk = tmp_path / f"walk_{controller}"
    args = ["--robot", str(robot_yaml), "--controller", controller, "--duration", "6"]
    assert main(["walk", *args, "--effects", "none", "--out", str(walk)]) == 0
    summary = json.loads((walk / "summary.json").read_text(encoding="utf-8"))
    assert not summary["fell"], summary["fall_kind"]
    assert summary["mean_speed_mps"] == pytest.approx(0.2, rel=0.15)
