"""The kinematic state estimator against the design model's own forward kinematics."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from zmpkit.robots.nao import NAO_DRIVEN_JOINTS, nao_ik_model
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sim.names import IMU_SITE, ft_site, sole_site
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.state_estimator import KinematicStateEstimator

FEET = ("left", "right")


def _posed(base_xyz, base_rpy, joints: dict[str, float]):
    model = nao_ik_model()
    data = mujoco.MjData(model)
    data.qpos[:3] = base_xyz
    mujoco.mju_euler2Quat(data.qpos[3:7], np.asarray(base_rpy, dtype=float), "xyz")
    for name, angle in joints.items():
        data.qpos[model.joint(name).qposadr[0]] = angle
    data.qpos[model.joint("RHipYawPitch").qposadr[0]] = joints.get("LHipYawPitch", 0.0)
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    return model, data


def _estimator(model, threshold_n=5.0):
    return KinematicStateEstimator(
        model, NAO_DRIVEN_JOINTS,
        {f: sole_site(f) for f in FEET}, {f: ft_site(f) for f in FEET}, IMU_SITE, threshold_n, 0.01,
    )  # fmt: skip


def _measurement(model, data, joints, force_world, moment_world) -> WalkMeasurement:
    m = WalkMeasurement.empty(NAO_DRIVEN_JOINTS, FEET)
    m.q_meas_rad[:] = [joints.get(j, 0.0) for j in NAO_DRIVEN_JOINTS]
    mujoco.mju_mat2Quat(m.imu_quaternion, data.site(IMU_SITE).xmat)
    for i, foot in enumerate(FEET):
        rotation = data.site(ft_site(foot)).xmat.reshape(3, 3)
        m.force_in_sensor[i] = rotation.T @ force_world[i]
        m.moment_in_sensor[i] = rotation.T @ moment_world[i]
    return m


@pytest.mark.parametrize(
    ("base_xyz", "base_rpy"),
    [((0.0, 0.0, 0.30), (0.0, 0.0, 0.0)), ((0.42, -0.13, 0.31), (0.03, -0.05, 0.4))],
)
def test_com_and_zmp_equal_the_model_when_the_feet_are_where_planned(base_xyz, base_rpy) -> None:
    joints = {"LHipPitch": -0.4, "LKneePitch": 0.8, "LAnklePitch": -0.35, "RHipPitch": -0.5,
              "RKneePitch": 0.9, "RAnklePitch": -0.45, "LHipYawPitch": -0.1, "LHipRoll": 0.05,
              "RAnkleRoll": -0.04}  # fmt: skip
    model, data = _posed(base_xyz, base_rpy, joints)
    force = np.array([[1.0, -2.0, 18.0], [-0.5, 1.5, 30.0]])
    moment = np.array([[0.3, -0.2, 0.01], [-0.1, 0.4, 0.0]])
    m = _measurement(model, data, joints, force, moment)
    soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
    estimator = _estimator(model)
    estimator.update(m, soles)
    np.testing.assert_allclose(estimator.com_in_world, data.subtree_com[1], atol=1e-9)
    sensors = np.array([data.site(ft_site(f)).xpos for f in FEET])
    expected = zmp_in_world(force[None], moment[None], sensors[None], 5.0)[0]
    np.testing.assert_allclose(estimator.zmp_in_world, expected, atol=1e-9)
    np.testing.assert_allclose(estimator.force_z_n, force[:, 2], atol=1e-9)


def test_a_foot_off_its_plan_moves_the_estimate_by_its_share_of_the_weight() -> None:
    """Anchor Δ = Σ F_z,i (ŝ_i - s_i) / Σ F_z,i: the left foot 1 cm off its plan carrying a
    third of the weight moves the CoM estimate by a third of a centimetre."""
    model, data = _posed((0.0, 0.0, 0.3), (0.0, 0.0, 0.0), {})
    force = np.array([[0.0, 0.0, 10.0], [0.0, 0.0, 20.0]])
    m = _measurement(model, data, {}, force, np.zeros((2, 3)))
    soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
    soles[0, 0] += 0.01
    estimator = _estimator(model)
    estimator.update(m, soles)
    shift = estimator.com_in_world - data.subtree_com[1]
    np.testing.assert_allclose(shift, [0.01 / 3.0, 0.0, 0.0], atol=1e-12)


def test_a_swing_foot_is_placed_by_the_stance_foot_where_it_really_is() -> None:
    """Leg odometry: the right foot alone in contact, 2 cm off where the walk says, places the
    robot, and with it the swing (left) foot, 2 cm off its design pose: ``s_i + Δ``."""
    joints = {"LHipPitch": -0.6, "LKneePitch": 1.0, "LAnklePitch": -0.4}  # left foot raised
    model, data = _posed((0.1, 0.05, 0.3), (0.0, 0.0, 0.0), joints)
    force = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 45.0]])  # the left foot carries nothing
    m = _measurement(model, data, joints, force, np.zeros((2, 3)))
    soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
    said = soles.copy()
    said[1, :2] += (0.02, -0.01)  # where the walk says the stance foot is
    said[0] += (0.3, 0.3, 0.0)  # where it says the swing foot is: not read, it has no load
    estimator = _estimator(model)
    estimator.update(m, said)
    swing = [estimator.sole_in_world(0, axis) for axis in range(3)]
    np.testing.assert_allclose(swing, soles[0] + (0.02, -0.01, 0.0), atol=1e-9)
    stance = [estimator.sole_in_world(1, axis) for axis in range(3)]
    np.testing.assert_allclose(stance, said[1], atol=1e-9)


def test_no_contact_gives_no_zmp_and_keeps_the_last_anchor() -> None:
    model, data = _posed((0.0, 0.0, 0.3), (0.0, 0.0, 0.0), {})
    soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
    estimator = _estimator(model)
    m = _measurement(model, data, {}, np.array([[0, 0, 20.0], [0, 0, 20.0]]), np.zeros((2, 3)))
    estimator.update(m, soles + np.array([0.02, 0.0, 0.0]))
    first = estimator.com_in_world.copy()
    m = _measurement(model, data, {}, np.zeros((2, 3)), np.zeros((2, 3)))
    estimator.update(m, soles)
    assert np.all(np.isnan(estimator.zmp_in_world))
    np.testing.assert_allclose(estimator.com_in_world, first, atol=1e-12)


@pytest.mark.parametrize("imu_yaw_error_rad", [0.0, 0.3, -0.6, 2.5])
def test_the_feet_give_the_yaw_that_a_drifting_imu_gets_wrong(imu_yaw_error_rad: float) -> None:
    """With the planned sole headings, the estimate is the model's own whatever the IMU's yaw
    says (a gyro bias turns it); roll and pitch still come from the IMU."""
    joints = {"LHipPitch": -0.4, "LKneePitch": 0.8, "LAnklePitch": -0.35, "RHipPitch": -0.5,
              "RKneePitch": 0.9, "RAnklePitch": -0.45, "LHipYawPitch": -0.1}  # fmt: skip
    model, data = _posed((0.42, -0.13, 0.31), (0.03, -0.05, 0.4), joints)
    force = np.array([[1.0, -2.0, 18.0], [-0.5, 1.5, 30.0]])
    moment = np.array([[0.3, -0.2, 0.01], [-0.1, 0.4, 0.0]])
    m = _measurement(model, data, joints, force, moment)
    turn = np.array([np.cos(imu_yaw_error_rad / 2), 0.0, 0.0, np.sin(imu_yaw_error_rad / 2)])
    mujoco.mju_mulQuat(m.imu_quaternion, turn, m.imu_quaternion.copy())  # yaw error in world
    soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
    yaws = np.array([np.arctan2(data.site(sole_site(f)).xmat[3], data.site(sole_site(f)).xmat[0])
                     for f in FEET])  # fmt: skip
    estimator = _estimator(model)
    estimator.update(m, soles, yaws)
    np.testing.assert_allclose(estimator.com_in_world, data.subtree_com[1], atol=1e-9)
    sensors = np.array([data.site(ft_site(f)).xpos for f in FEET])
    expected = zmp_in_world(force[None], moment[None], sensors[None], 5.0)[0]
    np.testing.assert_allclose(estimator.zmp_in_world, expected, atol=1e-9)
    assert estimator.yaw_correction_rad == pytest.approx(
        (-imu_yaw_error_rad + np.pi) % (2 * np.pi) - np.pi, abs=1e-9
    )
    unaided = _estimator(model)
    unaided.update(m, soles)  # the IMU's yaw alone
    miss = np.linalg.norm(unaided.com_in_world[:2] - data.subtree_com[1][:2])
    assert (miss > 1e-3) == (imu_yaw_error_rad != 0.0)


def test_weight_moving_onto_a_foot_off_its_plan_is_no_velocity() -> None:
    """A robot standing still whose weight moves, over ten ticks, from its right foot (where
    planned) to its left foot (1 cm ahead of its plan): the anchored CoM estimate moves by
    the 1 cm (its anchor's share), its velocity stays zero, as the robot's does."""
    model, data = _posed((0.0, 0.0, 0.3), (0.0, 0.0, 0.0), {})
    soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
    soles[0, 0] -= 0.01  # the plan puts the left foot 1 cm behind where it stands
    estimator = KinematicStateEstimator(
        model, NAO_DRIVEN_JOINTS, {f: sole_site(f) for f in FEET},
        {f: ft_site(f) for f in FEET}, IMU_SITE, 5.0, 0.01, velocity_time_constant_s=0.0,
    )  # fmt: skip
    first = None
    for share in np.linspace(0.0, 1.0, 11):  # of 45 N on the left foot
        force = np.array([[0.0, 0.0, 45.0 * share], [0.0, 0.0, 45.0 * (1.0 - share)]])
        estimator.update(_measurement(model, data, {}, force, np.zeros((2, 3))), soles)
        first = estimator.com_in_world.copy() if first is None else first
        np.testing.assert_allclose(estimator.com_velocity_in_world, 0.0, atol=1e-12)
    np.testing.assert_allclose(estimator.com_in_world - first, [-0.01, 0.0, 0.0], atol=1e-12)


def test_the_velocity_is_the_coms_relative_to_the_loaded_feet() -> None:
    """τ_v = 0: the velocity is Σ F_z,i Δ(c - s_i) / (T Σ F_z,i) of two posed ticks, from
    the design model's own forward kinematics (the feet carry 1:3 of the weight)."""
    period = 0.01
    before = {"LHipPitch": -0.4, "LKneePitch": 0.8, "RHipPitch": -0.5, "RKneePitch": 0.9}
    after = {"LHipPitch": -0.41, "LKneePitch": 0.81, "RHipPitch": -0.49, "RKneePitch": 0.88,
             "LAnklePitch": 0.01}  # fmt: skip
    force = np.array([[0.0, 0.0, 10.0], [0.0, 0.0, 30.0]])
    estimator = KinematicStateEstimator(
        model := nao_ik_model(), NAO_DRIVEN_JOINTS, {f: sole_site(f) for f in FEET},
        {f: ft_site(f) for f in FEET}, IMU_SITE, 5.0, period, velocity_time_constant_s=0.0,
    )  # fmt: skip
    relative = []
    for joints in (before, after):
        model, data = _posed((0.0, 0.0, 0.3), (0.0, 0.0, 0.0), joints)
        soles = np.array([data.site(sole_site(f)).xpos for f in FEET])
        relative.append(data.subtree_com[1] - soles)  # c - s_i, each foot a row
        estimator.update(_measurement(model, data, joints, force, np.zeros((2, 3))), soles)
    rates = (relative[1] - relative[0]) / period
    expected = (10.0 * rates[0] + 30.0 * rates[1]) / 40.0
    assert np.linalg.norm(expected) > 0.05  # the posture change moves the CoM
    np.testing.assert_allclose(estimator.com_velocity_in_world, expected, atol=1e-9)
