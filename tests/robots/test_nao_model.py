"""The virtual NAO: scenes compile and step without warnings, mass and CoM, truth file."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from zmpkit.errors import InputFileError
from zmpkit.robots.nao import (
    NAO_DRIVEN_JOINTS,
    NAO_MASS_KG,
    load_truth,
    make_nao,
    nao_feet_mounts,
    nao_ik_model,
)
from zmpkit.robots.nao.geometry import ANKLE_TO_SOLE_M, SOLE_CENTRE_AHEAD_OF_ANKLE_M
from zmpkit.sim.names import sole_site

EFFECT_SETS = ("none", "all", "M", "M,I", "G", "F", "S", "M,G,F")


@pytest.mark.parametrize("effects", EFFECT_SETS)
def test_scene_compiles_and_stands_one_second_without_warnings(effects: str) -> None:
    sim = make_nao(effects, seed=1)
    sim.command([0.0] * len(NAO_DRIVEN_JOINTS))
    sim.run(1.0)
    assert all(int(w.number) == 0 for w in sim.data.warning)
    assert sim.data.qpos[2] == pytest.approx(0.333, abs=0.002)  # still standing, legs straight
    assert np.all(np.isfinite(sim.encoders()))


def test_mass_matches_the_urdf_total() -> None:
    # nao-parameters.md §1: 5.305 kg, sum of the 25 massive links.
    model = nao_ik_model()
    assert model.body_subtreemass[1] == pytest.approx(NAO_MASS_KG, abs=0.002)


def test_crouch_com_height_matches_the_parameters_file() -> None:
    # §1: HipPitch/Knee/AnklePitch = -0.45/0.90/-0.45 rad, arms down -> CoM 0.2607 m.
    model = nao_ik_model()
    data = mujoco.MjData(model)
    for side in "LR":
        for joint, angle in (("HipPitch", -0.45), ("KneePitch", 0.9), ("AnklePitch", -0.45)):
            data.qpos[model.joint(side + joint).qposadr[0]] = angle
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    sole_z = data.site(sole_site("left")).xpos[2]
    com_height = data.subtree_com[1][2] - sole_z
    assert com_height == pytest.approx(0.2607, abs=0.005)


def test_sole_site_lies_ahead_of_and_below_the_ankle() -> None:
    model = nao_ik_model()
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    ankle = data.body("LFoot").xpos
    sole = data.site(sole_site("left")).xpos
    assert sole - ankle == pytest.approx(
        [SOLE_CENTRE_AHEAD_OF_ANKLE_M, 0.0, -ANKLE_TO_SOLE_M], abs=1e-9
    )
    assert pytest.approx(0.025) == SOLE_CENTRE_AHEAD_OF_ANKLE_M


def test_hip_yaw_pitch_is_one_motor() -> None:
    sim = make_nao("none")
    assert "RHipYawPitch" not in NAO_DRIVEN_JOINTS
    assert len(NAO_DRIVEN_JOINTS) == 11
    sim.command({"LHipYawPitch": -0.2})
    sim.run(0.5)
    q = sim.data.qpos
    left, right = (q[sim.model.joint(n).qposadr[0]] for n in ("LHipYawPitch", "RHipYawPitch"))
    assert left == pytest.approx(-0.2, abs=0.01)
    # The coupling is a soft joint equality and the robot still rocks from the hip motion at
    # 0.5 s: R lags L by up to 1.5 mrad with the truth's torso (0.8 mrad with the URDF's).
    assert right == pytest.approx(left, abs=2e-3)


def test_truth_turns_the_voltage_pid_into_joint_gains() -> None:
    truth = load_truth()
    knee = truth.motors["LKneePitch"]
    # k_link = s * g * K * N / R (module docstring of robots/nao/truth.py).
    expected = 0.7 * 1277.9 * 0.0195 * 130.85 / 6.44
    assert knee.kp_link == pytest.approx(expected)
    assert knee.gear_ratio == 130.85
    assert truth.motors["LHipRoll"].gear_ratio == 201.3
    assert knee.resistance == 6.44
    assert knee.voltage_limit == 21.6
    assert truth.inductances["LKneePitch"].inductance == pytest.approx(0.309e-3)


def test_truth_file_errors_name_the_file(tmp_path: Path) -> None:
    bad = tmp_path / "truth.yaml"
    bad.write_text("servo_rate_hz: 1000\n")
    with pytest.raises(InputFileError, match=r"truth\.yaml.*missing section"):
        load_truth(bad)


def test_feet_mounts_sit_under_the_ankles() -> None:
    mounts = nao_feet_mounts()
    assert set(mounts) == {"left", "right"}
    assert mounts["left"]["position"][1] == pytest.approx(0.05)
    assert mounts["right"]["position"][1] == pytest.approx(-0.05)
