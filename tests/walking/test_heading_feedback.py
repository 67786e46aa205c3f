"""IMU yaw feedback to the footsteps: the correction law, the ramp, the limits, and a walk."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.robots.registry import get_robot
from zmpkit.walking.heading_feedback import HeadingFeedback, HeadingFeedbackGains
from zmpkit.walking.swing import FeetTrajectories, FootTrajectory

N = 400  # frames of 10 ms: 4 s


def _feet() -> FeetTrajectories:
    """Left swings over frames 100–150 and 300–350, right over 200–250; straight ahead."""
    t = np.arange(N) * 0.01
    left_contact = np.ones(N, dtype=bool)
    left_contact[100:150] = False
    left_contact[300:350] = False
    right_contact = np.ones(N, dtype=bool)
    right_contact[200:250] = False
    zeros = np.zeros((N, 3))
    return FeetTrajectories(
        t,
        FootTrajectory(zeros.copy(), np.zeros(N), left_contact),
        FootTrajectory(zeros.copy(), np.zeros(N), right_contact),
        np.zeros(N),
        0.02,
    )


def _quaternion(yaw: float) -> np.ndarray:
    return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


def _run(feedback: HeadingFeedback, yaw_of_frame) -> None:
    for frame in range(N):
        feedback.update(frame, _quaternion(yaw_of_frame(frame)))


def test_a_constant_heading_error_is_taken_out_by_the_gain_at_each_lift_off() -> None:
    gains = HeadingFeedbackGains(gain_per_step=0.5, max_correction_rad=0.5,
                                 max_change_per_step_rad=0.5)  # fmt: skip
    feedback = HeadingFeedback(_feet(), gains)
    _run(feedback, lambda frame: 0.04)  # the robot turned 0.04 rad before the walk began...
    # ...but the IMU's start is the reference: no error, no correction
    assert feedback.correction_rad == 0.0
    feedback = HeadingFeedback(_feet(), gains)
    _run(feedback, lambda frame: 0.0 if frame < 50 else 0.04)  # turned 0.04 rad at frame 50
    # e_k is the mean error over the last two steps (the robot does not move here), and
    # c = −K Σ e_k over the three lift-offs
    errors = _lift_off_errors()
    for frame, expected in errors.items():
        assert feedback.heading_error_rad[frame] == pytest.approx(expected, rel=1e-12)
    assert errors[300] == pytest.approx(0.04)  # two whole steps after the turn: all of it
    assert feedback.correction_rad == pytest.approx(-0.5 * sum(errors.values()), rel=1e-12)


def _lift_off_errors() -> dict[int, float]:
    """e at the lift-offs 100, 200, 300 for a turn of 0.04 rad at frame 50, by hand.

    Step means: frames 0–100 (51 of 101 frames turned), 101–200 and 201–300 (all turned);
    e_k averages the step that ends at k with the one before (the first has none before).
    """
    first = 0.04 * 51 / 101
    return {100: first, 200: 0.5 * (first + 0.04), 300: 0.04}


def test_the_landing_yaw_ramps_over_the_swing_and_the_standing_foot_is_untouched() -> None:
    gains = HeadingFeedbackGains(gain_per_step=0.5, max_correction_rad=0.5,
                                 max_change_per_step_rad=0.5)  # fmt: skip
    plan = _feet()
    feedback = HeadingFeedback(plan, gains)
    _run(feedback, lambda frame: 0.0 if frame < 50 else 0.04)
    left = feedback.targets.left.yaw_in_world
    right = feedback.targets.right.yaw_in_world
    assert np.all(left[:100] == 0.0)  # before its first lift-off
    errors = _lift_off_errors()
    c1 = -0.5 * errors[100]
    c2 = c1 - 0.5 * errors[200]
    assert left[100] == pytest.approx(c1 * (0.5 - 0.5 * math.cos(math.pi / 50)))  # ramp start
    assert left[149] == pytest.approx(c1)  # landed turned by c₁
    assert np.all(np.diff(left[100:150]) <= 1e-15)  # monotone, no jump
    assert np.all(left[150:300] == pytest.approx(c1))  # held while it stands
    assert np.all(right[:200] == 0.0)  # the right foot stood still during the left swing
    assert right[249] == pytest.approx(c2)
    torso = feedback.targets.torso_yaw_in_world
    assert torso[260] == pytest.approx(0.5 * (left[260] + right[260]))
    assert np.all(plan.left.yaw_in_world == 0.0)  # the plan itself is not changed


def test_gain_zero_leaves_the_plan() -> None:
    feedback = HeadingFeedback(_feet(), HeadingFeedbackGains(gain_per_step=0.0))
    _run(feedback, lambda frame: 0.01 * frame)
    assert np.all(feedback.targets.left.yaw_in_world == 0.0)
    assert np.all(feedback.targets.torso_yaw_in_world == 0.0)


@given(st.lists(st.floats(-math.pi, math.pi), min_size=N, max_size=N))
@pytest.mark.slow
def test_the_correction_and_its_steps_stay_within_their_limits(yaws: list[float]) -> None:
    gains = HeadingFeedbackGains()
    feedback = HeadingFeedback(_feet(), gains)
    corrections = []
    for frame, yaw in enumerate(yaws):
        feedback.update(frame, _quaternion(yaw))
        corrections.append(feedback.correction_rad)
    c = np.array(corrections)
    assert np.all(np.abs(c) <= gains.max_correction_rad + 1e-12)
    assert np.all(np.abs(np.diff(c)) <= gains.max_change_per_step_rad + 1e-12)
    assert np.all(np.isfinite(feedback.targets.left.yaw_in_world))


def test_gains_out_of_range_are_refused() -> None:
    with pytest.raises(ParameterError, match="gain_per_step"):
        HeadingFeedbackGains(gain_per_step=1.5)
    with pytest.raises(ParameterError, match="max_correction_rad"):
        HeadingFeedbackGains(max_correction_rad=-0.1)


@pytest.mark.slow
def test_a_straight_zmpip_walk_keeps_its_heading_within_0_05_rad_over_10_s() -> None:
    config = WalkConfig(get_robot("nao"), controller="zmpip", figures=False)
    with_feedback = run_walk_trial(config).summary
    assert not with_feedback.fell
    assert with_feedback.heading_error_max_rad is not None
    assert with_feedback.heading_error_max_rad <= 0.05
    without = run_walk_trial(WalkConfig(get_robot("nao"), controller="zmpip", figures=False,
                                        heading_feedback=False)).summary  # fmt: skip
    assert without.heading_error_max_rad is not None
    assert with_feedback.heading_error_max_rad < without.heading_error_max_rad
