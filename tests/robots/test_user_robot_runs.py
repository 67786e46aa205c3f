"""A user's own biped, MJCF and URDF: robot init, robot check, a balance sweep and a walk.

The models are built here, in a temporary folder: a 8.4 kg biped with hip roll and pitch,
knee, ankle pitch and roll on each leg, written once as MJCF and once as URDF (the fixture
``robot_yaml`` of ``tests/robots/conftest.py``).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from helpers.biped import BIPED_MJCF, LEG_M
from zmpkit.cli import main
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.walk_dataset import read_series
from zmpkit.identify.params import BalanceParams
from zmpkit.pipelines.identify_balance import run_identify_balance
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.experiments import read_walk_folder


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


@pytest.mark.slow
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
    joints = get_robot(robot_yaml).require_walking().series_joints  # its time series reads
    header, table = read_series(walk / "timeseries.csv", joints)  # with its own joints' columns
    assert header[1:4] == [f"{joints[0]}_{q}" for q in ("cmd_rad", "meas_rad", "torque_nm")]
    assert joints[0].startswith("l_")
    assert table.shape[1] == len(header)
    experiment = read_walk_folder(walk, get_robot(robot_yaml))  # a fit re-plans its commands
    assert experiment.signals.joint_names == joints


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


_BIPED_TRUTH = """
servo_rate_hz: 1000.0
motor: {gear_ratio: 200.0, supply_voltage: 24.0, torque_constant: 0.02, resistance: 1.0,
        inductance: 1.0e-4, rotor_inertia: 1.0e-6}
pid: {kp: 400.0, ki: 200.0, kd: 4.0, integral_limit_link: 0.05}
friction: {coulomb_link: 0.05}
gear: {stiffness: 3000.0, damping: 1.0, backlash: 0.002, inertia_link: 1.0e-3}
flex:
  - {name: r_shank_flex, body: r_shank, axis: [0, 1, 0], anchor: [0, 0, -0.1],
     stiffness: [4000.0, 0.0, 0.0], damping: 1.0}
"""


def test_a_robot_file_with_a_truth_gets_the_effects(robot_yaml: Path) -> None:
    """``truth:`` in robot.yaml: motors, gears and a flexible shank; without it, no effects."""
    with pytest.raises(ParameterError, match="effects"):
        get_robot(robot_yaml).make_simulation("M")
    (robot_yaml.parent / "truth.yaml").write_text(_BIPED_TRUTH, encoding="utf-8")
    with_truth = robot_yaml.with_name("robot_with_truth.yaml")
    text = robot_yaml.read_text(encoding="utf-8")
    with_truth.write_text(text + "truth: truth.yaml\n", encoding="utf-8")
    robot = get_robot(with_truth)
    sim = robot.make_simulation("all")
    model = sim.model
    assert model.nu == len(robot.driven_joints) == 10
    assert model.joint("r_shank_flex").id > 0
    sim.step(500)  # it stands on its DC motors (stall: N K V / R = 96 N·m at the joint)
    weight = float(model.body_subtreemass[0]) * 9.81
    assert sim.ft("left")[2] + sim.ft("right")[2] == pytest.approx(weight, rel=0.05)
    assert robot.truth.default_path == (robot_yaml.parent / "truth.yaml").resolve()


def test_a_robot_file_names_a_missing_truth(robot_yaml: Path) -> None:
    with robot_yaml.open("a", encoding="utf-8") as handle:
        handle.write("truth: nowhere.yaml\n")
    with pytest.raises(InputFileError, match="truth: no such file"):
        get_robot(robot_yaml)


@pytest.mark.slow
def test_identify_sim_self_test_recovers_a_users_robot_with_a_truth(tmp_path: Path) -> None:
    """``zmpkit identify sim --self-test --quick`` on the biped with its servo truth: the fit
    catalogue derived from the truth (:mod:`zmpkit.robots.servo_fit`), balance steps
    replayed, the perturbed P gain and gear stiffness recovered."""
    model = tmp_path / "biped.xml"
    model.write_text(BIPED_MJCF, encoding="utf-8")
    robot_file = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(robot_file)]) == 0
    (tmp_path / "truth.yaml").write_text(_BIPED_TRUTH, encoding="utf-8")
    with robot_file.open("a", encoding="utf-8") as handle:
        handle.write("truth: truth.yaml\n")
    out = tmp_path / "fit"
    argv = ["identify", "sim", "--robot", str(robot_file), "--self-test", "--quick",
            "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    with (out / "recovery.csv").open(encoding="utf-8") as handle:
        rows = {row["parameter"]: row for row in csv.DictReader(handle)}
    assert set(rows) == {"pid_p_gain", "gear_stiffness"}
    for row in rows.values():
        assert abs(float(row["error_pct"])) < 2.0


def test_the_robot_file_gives_the_walk_speed_and_its_soft_servos(robot_yaml: Path) -> None:
    """walking.speed is the walk's default speed; servo_stiffness/_damping the feed-forward's."""
    from zmpkit.experiments.walk_config import WalkConfig

    assert get_robot(robot_yaml).require_walking().speed_mps == 0.2
    assert get_robot(robot_yaml).require_walking().servo_stiffness_nm_per_rad is None
    text = robot_yaml.read_text(encoding="utf-8")
    soft = robot_yaml.with_name("soft.yaml")
    walking = (
        "walking: {speed: 0.15, servo_stiffness: 30.0, servo_damping: 0.5, "
        "observer_com_noise: 0.1, observer_zmp_noise: 0.2}\n"
    )
    soft.write_text(text + walking, encoding="utf-8")
    defaults = get_robot(soft).require_walking()
    assert defaults.speed_mps == 0.15
    assert defaults.servo_stiffness_nm_per_rad == 30.0
    assert defaults.servo_damping_nm_s_per_rad == 0.5
    assert (defaults.observer_com_noise_m, defaults.observer_zmp_noise_m) == (0.1, 0.2)
    assert WalkConfig(robot=get_robot(soft)).speed_mps == 0.15
    assert WalkConfig(robot=get_robot(soft), speed_mps=0.05).speed_mps == 0.05
    bad = robot_yaml.with_name("bad.yaml")
    bad.write_text(text + "walking: {servo_damping: 0.5}\n", encoding="utf-8")
    with pytest.raises(InputFileError, match=r"walking.servo_damping.*needs walking.servo_st"):
        get_robot(bad)


def test_zmp_reads_a_log_with_a_users_robot_sensor_mounts(robot_yaml: Path) -> None:
    """``zmpkit zmp LOG --robot robot.yaml``: the biped's sole-plate sensors, a point load on
    each sole's centre line 3 cm ahead of the sensors gives a ZMP 3 cm ahead of them."""
    from helpers.ft_data import wrench_in_sensor, write_log
    from zmpkit.io import feet_from_mapping

    feet = feet_from_mapping(get_robot(robot_yaml).feet_mounts())
    row = [0.0]
    for side in ("right", "left"):
        m = feet[side]
        point = np.array([m.position[0] + 0.03, m.position[1], m.ground_height])
        row += list(wrench_in_sensor(point, np.array([0.0, 0.0, 40.0]), m.position, m.rotation))
    log = write_log(robot_yaml.parent / "log.csv", [row])
    out = robot_yaml.parent / "zmp"
    assert main(["zmp", str(log), "--robot", str(robot_yaml), "--out", str(out)]) == 0
    with (out / "zmp.csv").open(encoding="utf-8") as handle:
        (zmp,) = list(csv.DictReader(handle))
    assert float(zmp["zmp_x"]) == pytest.approx(feet["right"].position[0] + 0.03, abs=1e-12)
    assert float(zmp["zmp_y"]) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.slow
def test_identify_balance_finds_a_users_robot_from_any_folder(
    robot_yaml: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    """A dataset recorded with ``--robot robot.yaml`` (relative) records the file's absolute
    path, so ``identify balance`` takes the robot's design mass from another folder; a robot
    it cannot find is named with the two remedies; ``--robot`` names it instead."""
    monkeypatch.chdir(robot_yaml.parent)
    push = tmp_path / "push"
    args = ["--robot", robot_yaml.name, "--targets", "0,0.01,0.02,0.04", "--hold", "8"]
    assert main(["sim", "push", *args, "--out", str(push), "--workers", "1"]) == 0
    meta = json.loads((push / "meta.json").read_text(encoding="utf-8"))
    assert meta["robot"] == str(robot_yaml.resolve())
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    assert main(["identify", "balance", str(push), "--out", "fit"]) == 0
    mass = get_robot(robot_yaml).require_balance().mass_kg
    assert BalanceParams.from_yaml(elsewhere / "fit" / "params.yaml").mass == pytest.approx(mass)
    (push / "meta.json").write_text(json.dumps({**meta, "robot": "gone.yaml"}), encoding="utf-8")
    capsys.readouterr()
    assert main(["identify", "balance", str(push), "--out", "fit2"]) == 2
    assert (
        "unknown robot 'gone.yaml': name it with --robot NAME|PATH/robot.yaml, or give the "
        "pendulum mass with --mass KG"
    ) in capsys.readouterr().err
    named = ["identify", "balance", str(push), "--robot", str(robot_yaml), "--out", "fit3"]
    assert main(named) == 0
    assert BalanceParams.from_yaml(elsewhere / "fit3" / "params.yaml").mass == pytest.approx(mass)
    with pytest.raises(ParameterError, match="--robot names a step dataset's robot"):
        run_identify_balance(tmp_path / "steps.yaml", robot=str(robot_yaml))
