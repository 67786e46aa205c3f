"""The step adjustment's tick on a planned walk fed a DCM: what it writes, without a robot.

The DCM is the plan's plus an error; no simulator, no footholds measured (the swing lands
at its re-planned touchdown), so what is checked is the adjustment's own arithmetic: a walk
on its plan moves nothing, a step that cannot capture lands early and the next one lifts
as much earlier, and every landing stays within the legs' reach and off the other leg.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.planned_steps import planned_steps
from zmpkit.walking.step_adjustment import StepAdjustment, StepAdjustmentParameters
from zmpkit.walking.step_reach import StepReach

FEET = ("left", "right")
REACH = StepReach(leg_reach_m=0.076, hip_half_width_m=0.05, min_lateral_m=0.095)  # the NAO's
PUSHED_STEP = 6  # the step whose swing the error comes in


@pytest.fixture(scope="module")
def pattern():
    return generate_pattern(
        PatternConfig(command=WalkCommand(v_x=0.2), duration_s=8.0,
                      gait=GaitParameters(step_duration_s=0.5))
    )  # fmt: skip


def _planned(pattern, parameters: dict):
    """A step adjustment on the plan's soles, its targets, ω [1/s] and the plan's DCM [m]."""
    feet = {f: getattr(pattern.feet, f).position_in_world.copy() for f in FEET}
    soles = np.stack([feet[f] for f in FEET], axis=1)
    targets = {f: np.ascontiguousarray(soles[:, i]) for i, f in enumerate(FEET)}
    adjustment = StepAdjustment(
        pattern, FEET, REACH, StepAdjustmentParameters(**parameters), targets, soles
    )
    omega = math.sqrt(STANDARD_GRAVITY_MPS2 / pattern.config.com_height_m)
    com = pattern.com
    dcm = (com.com_position_in_world + com.com_velocity_in_world / omega)[:, :2]
    return adjustment, targets, omega, dcm


def _walk(pattern, error_m: tuple[float, float], at_frame: int, **parameters):
    """Run the adjustment over the whole walk; the DCM is the plan's plus ``error_m`` from
    ``at_frame`` on, carried by the LIPM's divergence (``e ← e^{ωT} e``) while it lasts.

    Returns the adjustment and the feet's targets, {foot: (N, 3)}.
    """
    adjustment, targets, omega, dcm = _planned(pattern, parameters)
    growth = math.exp(omega * pattern.config.control_period_s)
    error = np.zeros(2)
    for frame in range(1, pattern.time_s.size):
        before = frame - 1
        if before == at_frame:
            error[:] = error_m
        adjustment.update(frame, before, dcm[before, 0] + error[0], dcm[before, 1] + error[1])
        error *= growth
        error.clip(-0.3, 0.3, out=error)  # a bounded error: the tick sees a large one
    return adjustment, targets


def test_a_walk_on_its_plan_moves_no_foot(pattern) -> None:
    adjustment, targets = _walk(pattern, (0.0, 0.0), 0)
    for foot in FEET:
        assert np.array_equal(targets[foot], getattr(pattern.feet, foot).position_in_world)
    assert adjustment.events() == ()


def _touchdowns(z: np.ndarray) -> list[int]:
    """The frames a target sole comes down to the ground."""
    return [k for k in range(1, z.size) if z[k] <= 1e-12 < z[k - 1]]


def _lifts(z: np.ndarray) -> list[int]:
    return [k for k in range(1, z.size) if z[k] > 1e-12 >= z[k - 1]]


def test_a_step_that_cannot_capture_lands_early_and_the_next_lifts_as_much_earlier(
    pattern,
) -> None:
    steps = planned_steps(pattern, FEET)
    pushed, following = steps[PUSHED_STEP], steps[PUSHED_STEP + 1]
    at = pushed.lift + 5
    adjustment, targets = _walk(pattern, (0.0, -0.06), at, early_next_lift=True)  # outward
    event = next(e for e in adjustment.events() if e.step == PUSHED_STEP)
    assert not event.captured
    early = round(event.shortened_s / pattern.config.control_period_s)
    assert early > 0
    swing_z = targets[pushed.side][:, 2]
    assert pushed.touchdown - early in _touchdowns(swing_z)
    next_z = targets[following.side][:, 2]
    lifts = [k for k in _lifts(next_z) if abs(k - (following.lift + 1)) <= early + 1]
    assert lifts == [following.lift + 1 - early]


def test_without_early_lift_the_next_step_keeps_its_planned_lift(pattern) -> None:
    steps = planned_steps(pattern, FEET)
    pushed, following = steps[PUSHED_STEP], steps[PUSHED_STEP + 1]
    _, targets = _walk(pattern, (0.0, -0.06), pushed.lift + 5, early_next_lift=False)
    next_z = targets[following.side][:, 2]
    assert following.lift + 1 in _lifts(next_z)


@settings(max_examples=20, deadline=None)
@given(
    ex=st.floats(-0.12, 0.12),
    ey=st.floats(-0.12, 0.12),
    phase=st.floats(0.0, 0.6),
    early=st.booleans(),
)
def test_every_landing_is_within_reach_off_the_other_leg_and_in_time(
    pattern, ex: float, ey: float, phase: float, early: bool
) -> None:
    steps = planned_steps(pattern, FEET)
    pushed = steps[PUSHED_STEP]
    at = pushed.lift + int(phase * (pushed.touchdown - pushed.lift))
    adjustment, targets = _walk(pattern, (ex, ey), at, early_next_lift=early)
    fraction = adjustment.parameters.min_swing_fraction
    for step in steps[PUSHED_STEP : len(steps) - 1]:
        z = targets[step.side][:, 2]
        lift = max(k for k in _lifts(z) if k <= step.lift + 1)  # the plan's, or earlier
        down = min(k for k in _touchdowns(z) if k > lift)
        assert down <= step.touchdown  # never later than planned
        assert down - (lift - 1) >= math.ceil(fraction * (step.touchdown - step.lift))
        stance, land = targets[FEET[step.stance]][down], targets[step.side][down]
        c, s = step.cos_yaw, step.sin_yaw
        dx, dy = land[0] - stance[0], land[1] - stance[1]
        along, lateral = c * dx + s * dy, step.sign * (-s * dx + c * dy)
        assert lateral >= REACH.min_lateral_m - 1e-9  # no crossing
        u, v = 0.5 * along, 0.5 * lateral - REACH.hip_half_width_m
        assert math.hypot(u, v) <= REACH.leg_reach_m + 1e-9  # within both legs' reach


def _walk_held(pattern, error_m: tuple[float, float], frames: range, **parameters):
    """Run the adjustment over the whole walk; the DCM is the plan's plus ``error_m`` over
    ``frames`` (held, not grown: what the robot's own stepping does to it is not modelled).
    """
    adjustment, targets, _, dcm = _planned(pattern, parameters)
    for frame in range(1, pattern.time_s.size):
        ex, ey = error_m if frame - 1 in frames else (0.0, 0.0)
        adjustment.update(frame, frame - 1, dcm[frame - 1, 0] + ex, dcm[frame - 1, 1] + ey)
    return adjustment, targets


def test_two_steps_on_the_plans_timing_keep_the_touchdown_one_step_cannot(pattern) -> None:
    """8 cm of DCM along the walk over the pushed swing: one step of the NAO's reach cannot
    hold it and is re-timed (0.09 s early, uncaptured); the first of two steps keeps its
    planned touchdown and the second, on the plan's timing, captures (Koolen et al.'s
    two-step condition, :mod:`zmpkit.walking.two_step_capture`)."""
    steps = planned_steps(pattern, FEET)
    pushed = steps[PUSHED_STEP]
    frames = range(pushed.lift + 5, pushed.touchdown)
    one, _ = _walk_held(pattern, (0.08, 0.0), frames, two_step=False)
    two, targets = _walk_held(pattern, (0.08, 0.0), frames, two_step=True)
    first_one = next(e for e in one.events() if e.step == PUSHED_STEP)
    first_two = next(e for e in two.events() if e.step == PUSHED_STEP)
    assert first_one.shortened_s > 0.0
    assert not first_one.captured
    assert first_two.shortened_s == 0.0
    assert first_two.captured
    assert pushed.touchdown in _touchdowns(targets[pushed.side][:, 2])


@settings(max_examples=15, deadline=None)
@given(
    ex=st.floats(-0.12, 0.12),
    ey=st.floats(-0.12, 0.12),
    phase=st.floats(0.0, 0.6),
)
def test_two_step_landings_are_within_reach_off_the_other_leg_and_in_time(
    pattern, ex: float, ey: float, phase: float
) -> None:
    steps = planned_steps(pattern, FEET)
    pushed = steps[PUSHED_STEP]
    start = pushed.lift + int(phase * (pushed.touchdown - pushed.lift))
    _, targets = _walk_held(pattern, (ex, ey), range(start, pushed.touchdown), two_step=True)
    for step in steps[PUSHED_STEP : len(steps) - 1]:
        z = targets[step.side][:, 2]
        lift = max(k for k in _lifts(z) if k <= step.lift + 1)
        down = min(k for k in _touchdowns(z) if k > lift)
        assert down <= step.touchdown
        stance, land = targets[FEET[step.stance]][down], targets[step.side][down]
        c, s = step.cos_yaw, step.sin_yaw
        dx, dy = land[0] - stance[0], land[1] - stance[1]
        along, lateral = c * dx + s * dy, step.sign * (-s * dx + c * dy)
        assert lateral >= REACH.min_lateral_m - 1e-9
        u, v = 0.5 * along, 0.5 * lateral - REACH.hip_half_width_m
        assert math.hypot(u, v) <= REACH.leg_reach_m + 1e-9
