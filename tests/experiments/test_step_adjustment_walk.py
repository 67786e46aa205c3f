"""A pushed walk that moves its steps: where it steps, and that it says when it cannot capture."""

from __future__ import annotations

import math

import pytest

from zmpkit.experiments.robustness import RobustnessCase
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_disturbances import Push
from zmpkit.pipelines.walk_document import walk_checks
from zmpkit.robots.registry import get_robot
from zmpkit.walking.gait import StepLimits
from zmpkit.walking.step_events import NOT_CAPTURED

SEPARATION_M = 0.1  # the built-in walker's feet [m]


@pytest.fixture(scope="module")
def outward_push():
    """20 N × 0.1 s sideways outward over the right stance foot while the left one swings.

    The sweep's case ``push 20 N -y @ 0.25``, walked 6 s with the step adjustment on: the
    DCM runs to the right of the right foot, where no step of the left foot can go.
    """
    case = RobustnessCase("zmpip", push_n=20.0, push_dir="-y", push_phase=0.25)
    config = case.walk_config(get_robot("nao"), "all", 6.0, 0, step_adjustment=True)
    return config, run_walk_trial(config)


def test_a_step_that_cannot_capture_is_said_so_and_does_not_cross(outward_push) -> None:
    config, trial = outward_push
    (push,) = config.pushes
    events = [e for e in trial.record.step_events if e.time_s >= push.time_s]
    first = events[0]
    assert first.side == "left"  # the swing foot when the push came
    assert first.dcm_error_m[1] < -0.02  # pushed to the right
    assert not first.captured
    assert first.dcm_error_left_m > 0.0
    clearance = SEPARATION_M - StepLimits().min_foot_separation_m
    assert -clearance - 1e-9 <= first.shift_m[1] <= 0.0  # inwards, never across the right foot
    summary = trial.summary
    assert summary.adjusted_steps == len(trial.record.step_events)
    assert summary.uncaptured_steps >= 1
    assert any(NOT_CAPTURED in text for text in summary.step_events)
    check = next(c for c in walk_checks(summary) if "adjusted step" in c.name)
    assert check.status == "missed"
    assert NOT_CAPTURED in check.detail


def test_a_walk_that_is_not_pushed_moves_no_step() -> None:
    case = RobustnessCase("dcm")
    config = case.walk_config(get_robot("nao"), "all", 3.0, 0, step_adjustment=True)
    trial = run_walk_trial(config)
    assert not trial.summary.fell
    assert trial.record.step_events == ()


def test_a_diagonal_push_is_a_unit_vector() -> None:
    fx, fy = Push.parse("30@4:-x+y").force_in_world(4.05)
    assert math.hypot(fx, fy) == pytest.approx(30.0)
    assert fx < 0.0 < fy
