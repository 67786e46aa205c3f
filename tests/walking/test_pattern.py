"""The whole pattern (paper B's walk) and the swing-foot trajectories."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.robots.nao import NAO_WALKING_COM_HEIGHT_M
from zmpkit.walking import (
    PatternConfig,
    PreviewController,
    WalkCommand,
    foot_trajectories,
    generate_pattern,
    minimum_jerk,
    pattern_sample_times,
    plan_footsteps,
    swing_height,
)

DT = 0.01
#: Same walk and numbers as in test_walking_preview (measured RMS 1.41 mm, max 6.57 mm).
TRACKING_RMS_TOLERANCE_M = 1.6e-3
TRACKING_MAX_TOLERANCE_M = 7.5e-3


@pytest.fixture(scope="module")
def pattern():
    return generate_pattern()  # 0.2 m/s, 0.5 s steps, 10 s, dt 10 ms, z_c 0.26 m


def test_default_pattern_is_paper_b_walk_on_one_time_grid(pattern) -> None:
    n = round((1.0 + 20 * 0.5 + 0.1 + 1.5) / DT) + 1
    assert pattern.time_s.shape == (n,)
    np.testing.assert_allclose(np.diff(pattern.time_s), DT)
    assert len(pattern.footsteps.steps) == 20
    for array in (
        pattern.zmp_reference_in_world,
        pattern.com.zmp_in_world,
        pattern.feet.left.position_in_world[:, :2],
        pattern.zmp_offset_in_world,
    ):
        assert array.shape == (n, 2)
    assert pattern.com_position_in_world.shape == (n, 3)
    np.testing.assert_array_equal(pattern.com_position_in_world[:, 2], NAO_WALKING_COM_HEIGHT_M)
    assert pattern_sample_times(pattern.config).shape == (n,)


def test_pattern_tracks_and_its_zmp_is_the_cart_table_output(pattern) -> None:
    com = pattern.com
    error = com.zmp_in_world - pattern.linear_zmp_reference.zmp_in_world
    assert np.all(np.sqrt(np.mean(error**2, axis=0)) < TRACKING_RMS_TOLERANCE_M)
    assert np.all(np.abs(error).max(axis=0) < TRACKING_MAX_TOLERANCE_M)
    cart_table = com.com_position_in_world - 0.26 / 9.81 * com.com_acceleration_in_world
    np.testing.assert_allclose(com.zmp_in_world, cart_table, rtol=0, atol=1e-15)


def test_zmp_offset_is_added_and_tracked_by_superposition(pattern) -> None:
    t = pattern.time_s
    # A half-sine per step, zero before the walk: paper B's modifier shape, 5 mm forward.
    offset = np.zeros((t.size, 2))
    walking = (t > 1.0) & (t < 11.0)
    offset[walking, 0] = 0.005 * np.abs(np.sin(np.pi * (t[walking] - 1.0) / 0.5))
    shifted = generate_pattern(pattern.config, offset, gains=pattern.gains)
    np.testing.assert_array_equal(
        shifted.zmp_reference_in_world, pattern.linear_zmp_reference.zmp_in_world + offset
    )
    alone = PreviewController(pattern.gains).run(offset[:, 0], offset[:, 1])
    np.testing.assert_allclose(
        shifted.com.com_position_in_world - pattern.com.com_position_in_world,
        alone.com_position_in_world,
        rtol=0,
        atol=1e-12,
    )


def test_bad_offset_and_foreign_gains_are_refused(pattern) -> None:
    n = pattern.time_s.size
    with pytest.raises(ParameterError, match=rf"zmp_offset must have shape \({n}, 2\)"):
        generate_pattern(pattern.config, np.zeros((n - 1, 2)))
    other = PatternConfig(com_height_m=0.3)
    with pytest.raises(ParameterError, match="gains were computed for"):
        generate_pattern(other, gains=pattern.gains)
    with pytest.raises(ParameterError, match=r"PatternConfig.step_height_m must be >= 0 m"):
        PatternConfig(step_height_m=-0.01)
    with pytest.raises(ParameterError, match=r"control_period_s must be <= the single-support"):
        PatternConfig(control_period_s=0.5)
    with pytest.raises(ParameterError, match=r"give exactly one of n_steps or duration_s"):
        generate_pattern(PatternConfig(n_steps=6))


@pytest.mark.parametrize("derivative", [1, 2])
def test_swing_profiles_start_and_end_at_rest(derivative) -> None:
    ends = np.array([0.0, 1.0])
    np.testing.assert_allclose(minimum_jerk(ends, derivative), 0.0, atol=1e-12)
    np.testing.assert_allclose(swing_height(ends, 0.02, derivative), 0.0, atol=1e-12)
    # The analytic derivatives are the real ones (central differences inside the swing).
    tau, h = np.linspace(0.05, 0.95, 19), 1e-5
    for f in (minimum_jerk, lambda x, d=0: swing_height(x, 0.02, d)):
        numeric = (f(tau + h, derivative - 1) - f(tau - h, derivative - 1)) / (2 * h)
        np.testing.assert_allclose(f(tau, derivative), numeric, rtol=1e-6, atol=1e-9)


def test_swing_profile_values() -> None:
    np.testing.assert_allclose(minimum_jerk([0.0, 0.5, 1.0]), [0.0, 0.5, 1.0], atol=1e-15)
    tau = np.linspace(0.0, 1.0, 1001)
    assert swing_height(tau, 0.02).max() == pytest.approx(0.02, abs=1e-15)
    assert tau[np.argmax(swing_height(tau, 0.02))] == pytest.approx(0.5)
    with pytest.raises(ParameterError, match=r"derivative must be an integer in 0..3, got 4"):
        minimum_jerk(tau, 4)


def test_feet_land_on_their_footsteps_and_stay_put(pattern) -> None:
    feet, plan, t = pattern.feet, pattern.footsteps, pattern.time_s
    for step in plan.steps:
        foot = feet.left if step.side == "left" else feet.right
        landed = np.searchsorted(t, step.t_end - 1e-9)
        np.testing.assert_allclose(
            foot.position_in_world[landed], [step.x, step.y, 0.0], atol=1e-12
        )
        swinging = (t > step.t_start + 1e-9) & (t < step.t_end - 1e-9)
        assert not foot.in_contact[swinging].any()
        assert foot.position_in_world[swinging, 2].max() == pytest.approx(0.02)  # tau = 1/2
    for foot in (feet.left, feet.right):
        ground = foot.position_in_world[foot.in_contact]
        np.testing.assert_array_equal(ground[:, 2], 0.0)
        moved = np.linalg.norm(np.diff(foot.position_in_world, axis=0), axis=1)
        both = foot.in_contact[1:] & foot.in_contact[:-1]
        assert moved[both].max() == pytest.approx(0.0, abs=1e-15)  # no sliding on the ground


def test_sampled_feet_leave_and_meet_the_ground_smoothly(pattern) -> None:
    # Zero velocity and acceleration at the ends: the first swing sample moves by O(tau^3).
    feet, t = pattern.feet, pattern.time_s
    tau_1 = DT / pattern.footsteps.gait.single_support_s
    step = pattern.footsteps.steps[3]
    foot = feet.left if step.side == "left" else feet.right
    lift = int(np.searchsorted(t, step.t_start - 1e-9))  # the sample at tau = 0
    travel = step.x - pattern.footsteps.steps[1].x  # same foot, two steps earlier
    first_move = np.linalg.norm(
        foot.position_in_world[lift + 1, :2] - foot.position_in_world[lift, :2]
    )
    assert first_move <= 10 * tau_1**3 * travel + 1e-15
    assert foot.position_in_world[lift + 1, 2] <= 64 * tau_1**3 * 0.02 + 1e-15
    land = int(np.searchsorted(t, step.t_end - 1e-9))  # the sample at tau = 1
    last_move = np.linalg.norm(
        foot.position_in_world[land, :2] - foot.position_in_world[land - 1, :2]
    )
    assert last_move <= 10 * tau_1**3 * travel + 1e-15
    assert foot.position_in_world[land - 1, 2] <= 64 * tau_1**3 * 0.02 + 1e-15


def test_torso_yaw_is_the_mean_of_the_feet_yaws_on_a_turning_walk() -> None:
    plan = plan_footsteps(WalkCommand(0.1, 0.0, 0.4), n_steps=10)
    feet = foot_trajectories(plan, DT, 0.015)
    np.testing.assert_allclose(
        feet.torso_yaw_in_world, (feet.left.yaw_in_world + feet.right.yaw_in_world) / 2
    )
    left, right = plan.final_feet()
    assert feet.torso_yaw_in_world[-1] == pytest.approx(left.yaw) == pytest.approx(right.yaw)
    # Left steps 0, 2, 4, 6, 8 turn by 2 omega T = 0.4 rad; step 9 closes.
    assert feet.torso_yaw_in_world[-1] == pytest.approx(5 * 0.4)
    assert np.all(np.diff(feet.torso_yaw_in_world) >= -1e-15)  # turns one way only


def test_swing_refuses_bad_arguments() -> None:
    plan = plan_footsteps(WalkCommand(), n_steps=4)
    with pytest.raises(ParameterError, match=r"step_height_m must be >= 0 m, got -0.1 m"):
        foot_trajectories(plan, DT, -0.1)
    with pytest.raises(ParameterError, match=r"dt_s must be <= the single-support time 0.4 s"):
        foot_trajectories(plan, 0.45, 0.02)


@pytest.mark.parametrize(
    "command",
    [(0.0, 0.1, 0.0), (0.0, 0.0, 0.5), (0.1, 0.05, 0.3), (-0.1, 0.0, 0.0), (0.0, 0.0, 0.0)],
    ids=["sideways", "turn-in-place", "curve", "backward", "step-in-place"],
)
def test_every_walk_ends_with_the_com_at_rest_between_the_feet(command) -> None:
    # Measured for all five: |c - centre| <= 1.7e-6 m, |c_dot| <= 1.05e-5 m/s.
    config = PatternConfig(command=WalkCommand(*command), duration_s=None, n_steps=9)
    pattern = generate_pattern(config)
    left, right = pattern.footsteps.final_feet()
    centre = [(left.x + right.x) / 2, (left.y + right.y) / 2]
    np.testing.assert_allclose(pattern.com.com_position_in_world[-1], centre, atol=1e-5)
    assert np.abs(pattern.com.com_velocity_in_world[-1]).max() < 5e-5


@settings(max_examples=15, deadline=None)
@given(
    forward=st.floats(-0.04, 0.04),
    turn=st.floats(-0.4, 0.4),
    lateral=st.floats(-0.05, 0.05),
)
def test_the_zmp_reference_sits_forward_m_along_each_stance_sole(
    forward: float, turn: float, lateral: float
) -> None:
    """In single support the reference is the stance sole's centre plus ``forward`` along
    the sole's heading, on any walk (turning, sideways), whatever else the plan does."""
    from zmpkit.walking.zmp_reference import linear_zmp_reference

    plan = plan_footsteps(WalkCommand(0.1, lateral, turn), n_steps=8)
    centred = linear_zmp_reference(plan, DT)
    moved = linear_zmp_reference(plan, DT, forward)
    for k, step in enumerate(plan.steps):
        stance = plan.stance_before(k)
        i = int(np.searchsorted(moved.time_s, 0.5 * (step.t_start + step.t_end)))
        expected = np.array([math.cos(stance.yaw), math.sin(stance.yaw)]) * forward
        np.testing.assert_allclose(
            moved.zmp_in_world[i] - centred.zmp_in_world[i], expected, atol=1e-12
        )


def test_a_zmp_point_beyond_a_quarter_of_the_sole_is_refused() -> None:
    with pytest.raises(ParameterError, match=r"zmp_forward_m must lie within a quarter"):
        PatternConfig(zmp_forward_m=0.05)  # the default sole is 0.16 m long: ±0.04 m
    assert PatternConfig(zmp_forward_m=-0.04).zmp_forward_m == -0.04
