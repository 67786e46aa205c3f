"""Foot damping control: its law in closed form, the ankles it finds, its sign on a walk."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ModelError, ParameterError
from zmpkit.experiments.walk import sensor_layout
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_trial import simulate_walk
from zmpkit.robots.registry import get_robot
from zmpkit.walking import generate_pattern
from zmpkit.walking.foot_damping import (
    AnkleJoints,
    FootDamping,
    FootDampingParameters,
    ankle_joints,
)
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.walk_controllers import DcmParameters, DcmWalk

DT = 0.01
JOINTS = ("hip", "pitch", "roll")
ANKLE = AnkleJoints("pitch", "roll", 1.0, 1.0)


def _damping(a_x: float, a_y: float, leak: float = 0.5, limit: float = 0.2) -> FootDamping:
    parameters = FootDampingParameters((a_x, a_y), leak, 0.05, limit)
    return FootDamping(parameters, {"left": ANKLE}, JOINTS, DT)


@settings(max_examples=40, deadline=None)
@given(
    error_x=st.floats(-0.02, 0.02),
    error_y=st.floats(-0.02, 0.02),
    force_z=st.floats(5.0, 60.0),
    steps=st.integers(1, 200),
)
def test_a_constant_error_gives_the_first_order_response_in_closed_form(
    error_x, error_y, force_z, steps
) -> None:
    """θ_{k+1} = (1 - dt/T) θ_k + dt A F e: θ_n = A F e T (1 - (1 - dt/T)^n), signed per axis."""
    a_x, a_y, leak = 0.1, 0.05, 0.5
    damping = _damping(a_x, a_y, leak)
    for _ in range(steps):
        damping.update(np.array([error_x, error_y]), np.array([force_z]), np.zeros(1), 1.0)
    decay = 1.0 - (1.0 - DT / leak) ** steps
    expected = (a_x * force_z * error_x * leak * decay, -a_y * force_z * error_y * leak * decay)
    np.testing.assert_allclose(damping.angle_rad[0], expected, rtol=1e-9, atol=1e-15)


def test_the_error_is_read_in_the_foot_s_frame() -> None:
    """A foot turned 90° left: a ZMP wanted along world +x lies to its right (local -y)."""
    damping = _damping(0.1, 0.1)
    damping.update(np.array([0.01, 0.0]), np.array([50.0]), np.array([math.pi / 2]), 1.0)
    pitch, roll = damping.angle_rad[0]
    assert pitch == pytest.approx(0.0, abs=1e-15)
    assert roll == pytest.approx(DT * 0.1 * 50.0 * 0.01)  # right edge down: +θ_x


def test_a_foot_in_the_air_only_returns_to_the_plan_and_the_angle_is_clamped() -> None:
    damping = _damping(10.0, 10.0, limit=0.05)
    for _ in range(20):
        damping.update(np.array([0.05, -0.05]), np.array([50.0]), np.zeros(1), 1.0)
    np.testing.assert_allclose(damping.angle_rad[0], [0.05, 0.05])
    damping.update(np.array([0.05, -0.05]), np.array([0.5]), np.zeros(1), 1.0)  # lifted
    np.testing.assert_allclose(damping.angle_rad[0], [0.05 * (1 - DT / 0.05)] * 2)
    damping.update(np.full(2, np.nan), np.array([50.0]), np.zeros(1), 1.0)  # no ZMP: leak only
    np.testing.assert_allclose(damping.angle_rad[0], [0.04 * (1 - DT / 0.5)] * 2)


def test_apply_adds_each_correction_with_its_joint_s_sign() -> None:
    flipped = AnkleJoints("pitch", "roll", -1.0, 1.0)
    damping = FootDamping(FootDampingParameters((0.1, 0.1)), {"right": flipped}, JOINTS, DT)
    damping.angle_rad[0] = [0.02, -0.01]
    q = np.array([0.3, 0.1, 0.0])
    damping.apply(q)
    np.testing.assert_allclose(q, [0.3, 0.1 - 0.02, -0.01])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"admittance_rad_per_n_m_s": (0.1,)}, r"must be \(A_x, A_y\)"),
        ({"admittance_rad_per_n_m_s": (-0.1, 0.0)}, "admittance_rad_per_n_m_s"),
        ({"max_angle_rad": 0.5}, "must be <= 0.2 rad"),
        ({"leak_time_constant_s": 0.0}, "leak_time_constant_s"),
    ],
)
def test_parameters_are_checked(kwargs, match) -> None:
    with pytest.raises(ParameterError, match=match):
        FootDampingParameters(**kwargs)


LEG = """
<mujoco><worldbody><body name="shank" pos="0 0 0.3"><joint name="knee" axis="0 1 0"/>
  <geom size="0.02 0.1" type="capsule"/>
  <body name="ankle" pos="0 0 -0.2"><joint name="a_pitch" axis="0 -1 0"/>
    <geom size="0.02" type="sphere"/>
    <body name="foot"><joint name="a_roll" axis="1 0 0"/><geom size="0.05 0.03 0.01" type="box"/>
      <site name="sole" pos="0 0 -0.01"/></body></body></body></worldbody></mujoco>
"""


def test_ankle_joints_are_the_two_hinges_nearest_the_sole_signed_by_their_axes() -> None:
    model = mujoco.MjModel.from_xml_string(LEG)
    assert ankle_joints(model, "sole") == AnkleJoints("a_pitch", "a_roll", -1.0, 1.0)
    with pytest.raises(ModelError, match="no site 'heel'"):
        ankle_joints(model, "heel")
    knee_only = LEG.replace('<joint name="a_roll" axis="1 0 0"/>', "")
    with pytest.raises(ModelError, match="not an ankle pitch and roll"):
        ankle_joints(mujoco.MjModel.from_xml_string(knee_only), "sole")  # knee + pitch


def test_the_walking_robot_s_ankles_are_found_in_its_ik_joints() -> None:
    robot = get_robot("nao")
    settings_ = robot.ik_settings
    for site in settings_.sole_sites.values():
        ankle = ankle_joints(robot.ik_model(), site)
        assert {ankle.pitch_joint, ankle.roll_joint} <= set(settings_.joint_names)
        assert "Pitch" in ankle.pitch_joint
        assert "Roll" in ankle.roll_joint


def _zmp_error_rms_x(admittance_x: float) -> float:
    """RMS of the sagittal ``p^d - p`` over a 3 s all-effects DCM walk [m].

    The stabiliser's CoM admittance is off, as it tracks the same ``p^d`` (the ankles' effect
    is seen alone), and its DCM feedback acts only beyond a 3 cm dead band (without the
    admittance it needs one to stand: see :mod:`zmpkit.walking.dcm_stabiliser`).
    """
    config = WalkConfig(get_robot("nao"), controller="dcm", duration_s=3.0, figures=False)
    robot = get_robot(config.robot, needs="walking")
    pattern = generate_pattern(config.pattern_config())
    model, ik = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, ik)
    sim = robot.make_simulation(config.effects, seed=config.seed)
    damping = FootDampingParameters((admittance_x, 0.0))
    controller = DcmWalk(pattern, model, ik, sensor_layout(sim, ik.sole_sites), sim.joint_names,
                         parameters=DcmParameters(com_admittance_per_s2=0.0, dcm_deadband_m=0.03,
                                                  foot_damping=damping))  # fmt: skip
    record = simulate_walk(sim, trajectory, controller=controller)
    assert not record.fell
    desired, measured = controller.desired_zmp_in_world, record.zmp_in_world()
    n = min(desired.shape[0], measured.shape[0])
    ok = np.all(np.isfinite(desired[:n]) & np.isfinite(measured[:n]), axis=1)
    return float(np.sqrt(np.mean((desired[:n, 0][ok] - measured[:n, 0][ok]) ** 2)))


@pytest.mark.slow
def test_on_the_walking_robot_the_ankles_bring_the_measured_zmp_towards_the_asked_one() -> None:
    """The physical sign: with the sagittal admittance on, ``p^d - p`` shrinks (all effects)."""
    assert _zmp_error_rms_x(0.1) < 0.8 * _zmp_error_rms_x(0.0)
