"""The legs' reach from the robot's model: its numbers on the built-in walker, and its limits."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.walking import generate_pattern
from zmpkit.walking.gait import StepLimits
from zmpkit.walking.ik import WalkingIk
from zmpkit.walking.step_reach import StepReach, step_reach


@pytest.fixture(scope="module")
def nao_reach() -> StepReach:
    robot = get_robot(DEFAULT_WALK_ROBOT)
    model, settings_ = robot.ik_model(), robot.ik_settings
    ik = WalkingIk(model, settings_)
    pattern = generate_pattern()
    ik.set_targets(pattern, 0)
    ik.solve(settings_.max_iterations * 10, 0.01)
    qpos = ik.configuration.data.qpos.copy()
    return step_reach(model, settings_, qpos, StepLimits().min_foot_separation_m)


def test_the_built_in_walker_s_reach_follows_from_its_legs(nao_reach: StepReach) -> None:
    """NAO: hips 0.1 m apart, a straight leg of 0.249 m (hip to sole centre) crouched to ~0.2 m."""
    assert nao_reach.hip_half_width_m == pytest.approx(0.05, abs=1e-6)
    assert 0.05 < nao_reach.leg_reach_m < 0.1
    assert nao_reach.max_along_m == pytest.approx(2.0 * nao_reach.leg_reach_m)
    assert nao_reach.min_lateral_m == pytest.approx(0.09 + 0.005)  # sole width + clearance


def test_a_landing_in_reach_is_kept() -> None:
    reach = StepReach(0.08, 0.05, 0.095)
    assert reach.limit(0.1, 0.12) == (0.1, 0.12)


_reach = st.builds(StepReach, st.floats(0.02, 0.2), st.floats(0.0, 0.1), st.floats(0.05, 0.15))


@settings(max_examples=300, deadline=None)
@given(reach=_reach, along=st.floats(-0.6, 0.6), lateral=st.floats(-0.3, 0.8))
def test_a_limited_landing_is_in_reach_and_never_crosses(reach, along, lateral) -> None:
    x, y = reach.limit(along, lateral)
    assert y >= reach.min_lateral_m  # the legs do not cross
    u, v = x / 2.0, y / 2.0 - reach.hip_half_width_m
    in_ellipse = math.hypot(u, v) <= reach.leg_reach_m * (1.0 + 1e-9)
    assert in_ellipse or y == reach.min_lateral_m  # only the no-crossing floor may lift it out
    if math.hypot(along / 2.0, lateral / 2.0 - reach.hip_half_width_m) <= reach.leg_reach_m:
        assert x == along
        assert y == max(lateral, reach.min_lateral_m)
