"""The virtual TEO: scenes compile and step, mass and CoM match paper A, sensors behave."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.robots.teo import (
    DEFAULT_TRUTH_PATH,
    TEO_BALANCE_MASS_KG,
    TEO_COM_HEIGHT_M,
    TEO_DRIVEN_JOINTS,
    load_truth,
    make_teo,
    teo_feet_mounts,
    teo_mjcf,
)
from zmpkit.robots.teo.model import SOLE_PLATE_MASS_KG
from zmpkit.sim.names import ft_site

G = 9.81
SCENES = ["none", "M", "M,I", "G", "F", "S", "all"]


def _zmp_x_world(sim, measured: bool) -> float:
    """Double-support ZMP x in the world, p_x = -(tau_y + h F_x) / F_z per foot, F_z-weighted."""
    num = den = 0.0
    for foot in sim.robot.feet:
        w = sim.ft(foot.foot) if measured else sim.ft_true(foot.foot)
        x_site = sim.data.site(foot.site).xpos[0]
        num += (x_site - (w[4] + foot.sole_height_m * w[0]) / w[2]) * w[2]
        den += w[2]
    return num / den


@pytest.mark.parametrize("effects", SCENES)
def test_scene_compiles_and_stands_one_second_without_warnings(effects: str) -> None:
    sim = make_teo(effects)
    sim.run(1.0)
    assert [w.number for w in sim.data.warning] == [0] * len(sim.data.warning)
    assert sim.data.subtree_com[0][2] == pytest.approx(TEO_COM_HEIGHT_M, rel=0.01)


def test_standing_mass_and_com_height_match_the_balance_model() -> None:
    model = mujoco.MjModel.from_xml_string(teo_mjcf("none"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert model.body_subtreemass[0] == pytest.approx(TEO_BALANCE_MASS_KG, rel=0.01)
    assert data.subtree_com[0][2] == pytest.approx(TEO_COM_HEIGHT_M, rel=0.01)


def test_static_vertical_forces_sum_to_weight_with_effects_off() -> None:
    sim = make_teo("none")
    sim.run(1.5)
    total_fz = sum(sim.ft(side)[2] for side in ("right", "left"))
    weight = sim.model.body_subtreemass[0] * G
    assert total_fz == pytest.approx(weight, rel=0.005)
    assert total_fz == pytest.approx(
        (sim.model.body_subtreemass[0] - 2 * SOLE_PLATE_MASS_KG) * G, rel=1e-3
    )


def test_sensor_offset_shows_in_the_measured_wrench_and_zmp() -> None:
    sim = make_teo("S", seed=3)
    sim.run(1.0)
    truth = load_truth()
    gain = 1.0 + truth.sensors.ft_gain_error
    measured, true = [], []
    for _ in range(100):
        sim.run(0.005)
        measured.append(sim.ft("right"))
        true.append(sim.ft_true("right"))
    bias = np.mean(measured, axis=0) - gain * np.mean(true, axis=0)
    np.testing.assert_allclose(bias, truth.ft_offsets["right"], atol=0.2)
    h = sim.robot.feet[0].sole_height_m
    w_meas, w_true = np.mean(measured, axis=0), np.mean(true, axis=0)
    zmp_meas = -(w_meas[4] + h * w_meas[0]) / w_meas[2]
    zmp_true = -(w_true[4] + h * w_true[0]) / w_true[2]
    w_model = gain * w_true + np.asarray(truth.ft_offsets["right"])  # closed form, no noise
    zmp_model = -(w_model[4] + h * w_model[0]) / w_model[2]
    assert zmp_meas - zmp_true == pytest.approx(zmp_model - zmp_true, rel=0.05)
    assert abs(zmp_meas - zmp_true) > 1e-3  # the offset moves the ZMP by more than 1 mm


def test_same_seed_gives_identical_sensor_output() -> None:
    def record(seed: int) -> np.ndarray:
        sim = make_teo("S", seed=seed)
        rows = []
        for _ in range(40):
            sim.run(0.005)
            rows.append(np.concatenate([sim.ft("right"), sim.ft("left"), *sim.imu()[:2]]))
        return np.array(rows)

    first = record(11)
    np.testing.assert_array_equal(first, record(11))
    assert not np.array_equal(first, record(12))


def test_ankle_command_moves_the_zmp_forward() -> None:
    sim = make_teo("none")
    sim.run(1.0)
    x0 = _zmp_x_world(sim, False)
    theta = 0.03
    sim.command({"right_ankle_frontal": -theta, "left_ankle_frontal": -theta})
    sim.run(2.5)
    lever = 0.7767  # dx_com/dtheta of the rigid model about the ankle axis [m]
    assert _zmp_x_world(sim, False) - x0 == pytest.approx(lever * np.sin(theta), rel=0.02)


def test_feet_mounts_match_the_model() -> None:
    mounts = teo_feet_mounts()
    sim = make_teo("none")
    for side, mount in mounts.items():
        np.testing.assert_allclose(sim.data.site(ft_site(side)).xpos, mount["position"], atol=1e-3)
        assert mount["rpy"] == [0.0, 0.0, 0.0]
        assert mount["sole_height"] == pytest.approx(0.010, abs=1e-3)


def test_driven_joints_follow_teo_order() -> None:
    assert TEO_DRIVEN_JOINTS[:6] == (
        "right_hip_axial",
        "right_hip_sagittal",
        "right_hip_frontal",
        "right_knee_frontal",
        "right_ankle_frontal",
        "right_ankle_sagittal",
    )
    assert len(TEO_DRIVEN_JOINTS) == 14


def test_unknown_joint_command_is_rejected() -> None:
    sim = make_teo("none")
    with pytest.raises(ParameterError, match="unknown joints"):
        sim.command({"elbow": 0.1})


def test_missing_truth_file_is_named(tmp_path) -> None:
    with pytest.raises(InputFileError, match=r"nope\.yaml"):
        load_truth(tmp_path / "nope.yaml")


def test_truth_file_missing_section_names_it(tmp_path) -> None:
    bad = tmp_path / "truth.yaml"
    bad.write_text("servo_rate_hz: 1000\n", encoding="utf-8")
    with pytest.raises(InputFileError, match="missing section 'joints'"):
        load_truth(bad)


def test_truth_file_unknown_gear_joint_is_named(tmp_path) -> None:
    text = DEFAULT_TRUTH_PATH.read_text(encoding="utf-8").replace(
        "joints: [right_hip_sagittal,", "joints: [right_elbow,", 1
    )
    bad = tmp_path / "truth.yaml"
    bad.write_text(text, encoding="utf-8")
    with pytest.raises(InputFileError, match=r"gear.joints: unknown joints \['right_elbow'\]"):
        load_truth(bad)


def test_all_effects_scene_has_the_truth_degrees_of_freedom() -> None:
    truth = load_truth()
    model = mujoco.MjModel.from_xml_string(teo_mjcf("all"))
    rigid = mujoco.MjModel.from_xml_string(teo_mjcf("none"))
    assert model.nv == rigid.nv + len(truth.gear_joints) + len(truth.flex)
    stages = sum(f.softening_stages - 1 for f in truth.flex if f.spring is not None)
    assert model.ntendon == len(truth.gear_joints) + stages
