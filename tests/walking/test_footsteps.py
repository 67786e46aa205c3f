"""Footstep planner and linear ZMP reference: invariants over random commands.

Sole size for the support polygons: 0.16 x 0.09 m (NAO's 158 x 88 mm rounded up,
nao-parameters.md §5), the planner's default ``FootShape``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from zmpkit.errors import ParameterError
from zmpkit.walking import (
    Footstep,
    FootstepPlan,
    GaitParameters,
    StepLimits,
    WalkCommand,
    linear_zmp_reference,
    plan_footsteps,
)

LIMITS = StepLimits()
SIGN = {"left": 1.0, "right": -1.0}
EPS = 1e-12
#: Containment slack for the support polygon test [m].
POLYGON_TOLERANCE_M = 1e-9

commands = st.builds(
    WalkCommand,
    v_x=st.floats(-0.4, 0.4),
    v_y=st.floats(-0.2, 0.2),
    omega=st.floats(-1.5, 1.5),
)
gaits = st.builds(
    GaitParameters,
    step_duration_s=st.sampled_from([0.3, 0.4, 0.5, 0.6, 0.8]),
    double_support_ratio=st.sampled_from([0.0, 0.1, 0.2, 0.3, 0.5]),
    initial_double_support_s=st.sampled_from([0.0, 0.5, 1.0]),
    final_double_support_s=st.sampled_from([0.0, 1.0]),
)
step_counts = st.integers(2, 14)


def relative(stance: Footstep, step: Footstep) -> tuple[float, float, float]:
    """Landing pose of ``step`` in the frame of ``stance``: x [m], y [m], yaw [rad]."""
    x, y = stance.to_local(step.x, step.y)
    return x, y, step.yaw - stance.yaw


def corners_in_world(foot: Footstep) -> np.ndarray:
    c, s = math.cos(foot.yaw), math.sin(foot.yaw)
    local = np.array(LIMITS.foot.corners_in_foot())
    return local @ np.array([[c, s], [-s, c]]) + [foot.x, foot.y]


def all_stances(plan: FootstepPlan):
    for k, step in enumerate(plan.steps):
        yield plan.stance_before(k), step


@settings(max_examples=150, deadline=None)
@given(commands, gaits, step_counts)
def test_sides_alternate_and_timing_is_regular(command, gait, n) -> None:
    plan = plan_footsteps(command, gait, n_steps=n)
    assert len(plan.steps) == n
    assert [s.index for s in plan.steps] == list(range(n))
    for k, (stance, step) in enumerate(all_stances(plan)):
        assert step.side != stance.side
        assert step.t_end - step.t_start == pytest.approx(gait.single_support_s)
        expected_lift = gait.initial_double_support_s + k * gait.step_duration_s
        assert step.t_start == pytest.approx(expected_lift + gait.double_support_s)


@settings(max_examples=150, deadline=None)
@given(commands, gaits, step_counts)
def test_every_step_respects_the_limits(command, gait, n) -> None:
    plan = plan_footsteps(command, gait, n_steps=n)
    s = gait.foot_separation_m
    for stance, step in all_stances(plan):
        x, y, yaw = relative(stance, step)
        assert abs(x) <= LIMITS.max_step_length_m + EPS
        assert SIGN[step.side] * y - s <= LIMITS.max_step_width_m + EPS
        assert abs(yaw) <= LIMITS.max_turn_rad + EPS


@settings(max_examples=150, deadline=None)
@given(commands, gaits, step_counts)
def test_feet_keep_their_lateral_clearance_and_never_turn_inward(command, gait, n) -> None:
    plan = plan_footsteps(command, gait, n_steps=n)
    inner_edge = LIMITS.foot.width_m / 2 + LIMITS.min_foot_clearance_m
    for stance, step in all_stances(plan):
        sign = SIGN[step.side]
        _, y, yaw = relative(stance, step)
        assert sign * y >= LIMITS.min_foot_separation_m - EPS
        assert sign * yaw >= -EPS  # outward turn or none: toes never point at the stance foot
        corners_y = [stance.to_local(*c)[1] for c in corners_in_world(step)]
        assert min(sign * cy for cy in corners_y) >= inner_edge - 1e-9


@settings(max_examples=150, deadline=None)
@given(commands, gaits, step_counts)
def test_walk_stops_with_feet_together_and_parallel(command, gait, n) -> None:
    plan = plan_footsteps(command, gait, n_steps=n)
    left, right = plan.final_feet()
    assert left.yaw == pytest.approx(right.yaw, abs=EPS)
    x, y, _ = relative(right, left)
    assert x == pytest.approx(0.0, abs=1e-12)
    assert y == pytest.approx(gait.foot_separation_m, abs=1e-12)


@settings(max_examples=100, deadline=None)
@given(st.floats(-0.4, 0.4), gaits, step_counts)
def test_straight_walk_covers_the_commanded_distance(v_x, gait, n) -> None:
    plan = plan_footsteps(WalkCommand(v_x, 0.0, 0.0), gait, n_steps=n)
    T, longest = gait.step_duration_s, LIMITS.max_step_length_m
    half = math.copysign(min(abs(v_x) * T / 2, longest), v_x)
    full = math.copysign(min(abs(v_x) * T, longest), v_x)
    # The first step is half, the last one closes, those in between are full.
    clamped = abs(v_x) * T / 2 > longest or (n >= 3 and abs(v_x) * T > longest)
    assert ("step_length" in plan.clamped_limits) == clamped
    left, right = plan.final_feet()
    midpoint_x = (left.x + right.x) / 2
    # Half a step, n - 2 full steps, closing step: v T (n - 3/2) = v T_walk - 1.5 v T.
    assert midpoint_x == pytest.approx(half + full * (n - 2), abs=1e-12)
    if not clamped:
        assert midpoint_x == pytest.approx(v_x * T * (n - 1.5), abs=1e-12)
        assert abs(midpoint_x - v_x * n * T) <= 1.5 * abs(v_x) * T + 1e-12
    assert (left.y + right.y) / 2 == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("v_y", [0.05, -0.05, 0.1])
def test_sideways_walk_opens_the_leading_foot_and_closes_the_other(v_y) -> None:
    n, gait = 9, GaitParameters()
    plan = plan_footsteps(WalkCommand(0.0, v_y, 0.0), gait, n_steps=n)
    lead = "left" if v_y > 0 else "right"
    width = min(2 * abs(v_y) * gait.step_duration_s, LIMITS.max_step_width_m)
    assert plan.steps[0].side == lead
    for stance, step in list(all_stances(plan))[:-1]:
        _, y, _ = relative(stance, step)
        opening = width if step.side == lead else 0.0
        assert abs(y) == pytest.approx(gait.foot_separation_m + opening)
    left, right = plan.final_feet()
    assert (left.y + right.y) / 2 == pytest.approx(math.copysign(width, v_y) * (n - 1) / 2)


@pytest.mark.parametrize("omega", [0.3, -0.3, 2.0])
def test_turn_in_place_turns_by_the_command_and_reports_clearance(omega) -> None:
    n, gait = 7, GaitParameters()
    plan = plan_footsteps(WalkCommand(0.0, 0.0, omega), gait, n_steps=n)
    turn = min(2 * abs(omega) * gait.step_duration_s, LIMITS.max_turn_rad)
    left, _ = plan.final_feet()
    assert left.yaw == pytest.approx(math.copysign(turn, omega) * (n - 1) / 2)
    assert ("turn" in plan.clamped_limits) == (2 * abs(omega) * gait.step_duration_s > 0.4)
    assert "foot_clearance" in plan.clamped_limits  # turned feet are pushed apart


def test_in_range_command_is_not_clamped_and_large_one_is() -> None:
    assert plan_footsteps(WalkCommand(0.2, 0.0, 0.0), duration_s=10.0).clamped_limits == ()
    plan = plan_footsteps(WalkCommand(0.5, 0.2, 0.0), n_steps=6)
    assert plan.was_clamped
    assert set(plan.clamped_limits) == {"step_length", "step_width"}


def test_duration_gives_steps_of_paper_b_walk() -> None:
    plan = plan_footsteps(WalkCommand(0.2, 0.0, 0.0), duration_s=10.0)
    assert len(plan.steps) == 20
    assert plan.duration_s == pytest.approx(1.0 + 20 * 0.5 + 0.1 + 1.5)
    kinds = [p.kind for p in plan.phases()]
    assert kinds[0] == kinds[-1] == "double"
    assert kinds[1:-1] == ["double", "single"] * 20


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({}, "give exactly one of n_steps or duration_s"),
        ({"n_steps": 4, "duration_s": 2.0}, "give exactly one of n_steps or duration_s"),
        ({"n_steps": 1}, r"n_steps must be an integer >= 2 \(start and closing step\), got 1"),
        ({"n_steps": 4, "first_side": "middle"}, "first_side must be one of"),
        ({"duration_s": -1.0}, r"duration_s must be > 0 s, got -1.0 s"),
    ],
)
def test_bad_planner_arguments_name_the_field(kwargs, message) -> None:
    with pytest.raises(ParameterError, match=message):
        plan_footsteps(WalkCommand(), **kwargs)


def test_inconsistent_geometry_is_refused() -> None:
    with pytest.raises(ParameterError, match=r"foot_separation_m must be >= foot width"):
        plan_footsteps(WalkCommand(), GaitParameters(foot_separation_m=0.08), n_steps=4)
    with pytest.raises(ParameterError, match=r"max_step_width_m must be >= 0.0226 m"):
        plan_footsteps(WalkCommand(), limits=StepLimits(max_step_width_m=0.01), n_steps=4)
    with pytest.raises(ParameterError, match=r"double_support_ratio must lie in \[0, 0.9\]"):
        GaitParameters(double_support_ratio=1.0)
    with pytest.raises(ParameterError, match=r"WalkCommand.v_x must be finite, got nan"):
        WalkCommand(v_x=float("nan"))


def feet_on_ground(plan: FootstepPlan, t: float) -> list[Footstep]:
    """The placements of the feet that are not swinging at time ``t``."""
    feet = []
    for side, initial in (("left", plan.initial_left), ("right", plan.initial_right)):
        placements = [initial, *(s for s in plan.steps if s.side == side)]
        if any(p.t_start < t < p.t_end for p in placements):
            continue
        feet.append([p for p in placements if p.t_end <= t][-1])
    return feet


@settings(max_examples=80, deadline=None)
@given(commands, gaits, st.integers(2, 8))
@pytest.mark.slow
def test_zmp_reference_stays_in_the_support_polygon(command, gait, n) -> None:
    plan = plan_footsteps(command, gait, n_steps=n)
    reference = linear_zmp_reference(plan, 0.01)
    for t, point in zip(reference.time_s, reference.zmp_in_world, strict=True):
        feet = feet_on_ground(plan, float(t))
        assert feet, f"no foot on the ground at t = {t}"
        hull = ConvexHull(np.vstack([corners_in_world(f) for f in feet]))
        distances = hull.equations[:, :2] @ point + hull.equations[:, 2]
        assert distances.max() <= POLYGON_TOLERANCE_M, f"ZMP outside at t = {t:.3f} s"


def test_zmp_reference_is_centred_at_the_ends_and_under_the_stance_foot() -> None:
    plan = plan_footsteps(WalkCommand(0.2, 0.05, 0.2), n_steps=8)
    reference = linear_zmp_reference(plan, 0.01)
    np.testing.assert_allclose(reference.zmp_in_world[0], [0.0, 0.0], atol=1e-15)
    left, right = plan.final_feet()
    centre = [(left.x + right.x) / 2, (left.y + right.y) / 2]
    np.testing.assert_allclose(reference.zmp_in_world[-1], centre, atol=1e-15)
    for k, step in enumerate(plan.steps):
        stance = plan.stance_before(k)
        inside = (reference.time_s >= step.t_start) & (reference.time_s <= step.t_end)
        np.testing.assert_allclose(reference.zmp_x_in_world[inside], stance.x, atol=1e-12)
        np.testing.assert_allclose(reference.zmp_y_in_world[inside], stance.y, atol=1e-12)


def test_zmp_reference_refuses_a_period_longer_than_a_step() -> None:
    plan = plan_footsteps(WalkCommand(), n_steps=4)
    with pytest.raises(ParameterError, match=r"dt_s must be <= the step duration 0.5 s"):
        linear_zmp_reference(plan, 0.6)
    with pytest.raises(ParameterError, match=r"dt_s must be > 0 s, got 0.0 s"):
        linear_zmp_reference(plan, 0.0)
