"""The DLIPM with ZMP feedback: PI closed forms, clamps, anti-windup, missing samples."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.allocations import traced_growth_and_peak
from zmpkit.control import (
    DlipmController,
    DlipmFeedbackController,
    GainSchedule,
    LipmController,
    PidGains,
    ZmpFeedbackGains,
)
from zmpkit.errors import ParameterError
from zmpkit.identify import ErrorModel

PAPER_A = ErrorModel("quadratic", (0.834, 1.024, -0.0004))  # paper A eq. 13
MASS_KG, LENGTH_M = 62.6, 0.893  # paper A §4.1
DT_S = 0.01
ANGLE_LIMIT_RAD = 0.3


def controller(
    gains: ZmpFeedbackGains, model: ErrorModel = PAPER_A, target_m: float = 0.0
) -> DlipmFeedbackController:
    dlipm = DlipmController(
        GainSchedule(model, MASS_KG, LENGTH_M),
        DT_S,
        angle_limit_rad=ANGLE_LIMIT_RAD,
        rate_limit_rad_s=2.0,
        support_polygon=(-0.12, 0.15),
    )
    fb = DlipmFeedbackController(dlipm, gains)
    fb.set_target(target_m)
    fb.reset()  # at rest on the target
    return fb


def test_constant_error_ramps_the_integral_at_ki_e() -> None:
    gains = ZmpFeedbackGains(0.0, 0.5, integral_limit_rad=1.0, output_limit_rad=1.0)
    fb = controller(gains)
    rest = fb.feedforward.steady_angle
    for _ in range(100):
        angle = fb.step(-0.01)  # error e = 0 - (-0.01) = 0.01 m
    # I = ki e t = 0.5 rad/(m s) * 0.01 m * 1 s
    assert fb.integral == pytest.approx(0.5 * 0.01 * 100 * DT_S, rel=1e-12)
    assert angle == pytest.approx(rest + fb.integral, abs=1e-12)


def test_proportional_part_is_kp_e() -> None:
    fb = controller(ZmpFeedbackGains(2.0, 0.0, integral_limit_rad=0.1, output_limit_rad=0.1))
    rest = fb.feedforward.steady_angle
    assert fb.step(0.02) == pytest.approx(rest - 2.0 * 0.02, abs=1e-12)
    assert fb.integral == 0.0


def test_integral_and_output_clamps_hold() -> None:
    gains = ZmpFeedbackGains(0.0, 10.0, integral_limit_rad=0.02, output_limit_rad=0.05)
    fb = controller(gains)
    for _ in range(1000):
        fb.step(-0.05)
    assert fb.integral == pytest.approx(0.02, abs=1e-15)
    assert fb.correction == pytest.approx(0.02, abs=1e-15)
    gains = ZmpFeedbackGains(5.0, 10.0, integral_limit_rad=0.5, output_limit_rad=0.05)
    fb = controller(gains)
    for _ in range(1000):
        fb.step(-0.05)
    assert fb.correction == pytest.approx(0.05, abs=1e-15)


def test_integrator_does_not_wind_while_saturated() -> None:
    # kp e alone (0.25 rad) saturates the 0.05 rad output: the integral must stay at 0
    gains = ZmpFeedbackGains(5.0, 1.0, integral_limit_rad=1.0, output_limit_rad=0.05)
    fb = controller(gains)
    for _ in range(2000):
        fb.step(-0.05)
    assert fb.integral == 0.0
    assert fb.correction == 0.05
    # the error reverses: the correction leaves the limit on the first tick (no wind-down)
    fb.step(0.001)
    assert fb.correction == pytest.approx(-5.0 * 0.001 - 1.0 * 0.001 * DT_S, abs=1e-12)


def test_angle_limit_also_stops_the_integral() -> None:
    gains = ZmpFeedbackGains(0.0, 1.0, integral_limit_rad=1.0, output_limit_rad=1.0)
    fb = controller(gains)
    for _ in range(100_000):
        fb.step(-0.1)
    integral = fb.integral
    # integration stopped one increment (ki e dt) short of the angle limit, and stays there
    assert ANGLE_LIMIT_RAD - 1.0 * 0.1 * DT_S <= fb.angle <= ANGLE_LIMIT_RAD
    for _ in range(100):
        fb.step(-0.1)
    assert fb.integral == integral


def test_missing_sample_holds_integral_and_correction() -> None:
    gains = ZmpFeedbackGains(1.0, 0.5, integral_limit_rad=0.1, output_limit_rad=0.1)
    fb = controller(gains, target_m=0.05)
    for _ in range(50):
        fb.step(0.04)
    integral, correction = fb.integral, fb.correction
    for _ in range(30):
        angle = fb.step(None)
        assert fb.integral == integral
        assert fb.correction == correction
        assert angle == pytest.approx(fb.feedforward.angle + correction, abs=1e-15)


def test_feedback_removes_the_offset_of_a_mis_scheduled_dlipm() -> None:
    """A plant 20 % stiffer than the schedule's model: the DLIPM alone misses, the PI not."""
    plant = ErrorModel("quadratic", (0.834, 1.024 * 0.8, 0.003))

    def measured(angle: float) -> float:
        return float(plant.predict(LENGTH_M * math.sin(angle)))

    target = 0.08
    gains = ZmpFeedbackGains.from_plant(LENGTH_M * 0.8 * 1.024, LENGTH_M, output_limit_rad=0.1)
    open_loop = controller(gains, target_m=0.0)
    open_loop.set_target(target)
    for _ in range(6000):
        angle = open_loop.feedforward.step()
    assert abs(measured(angle) - target) > 0.01  # > 12 % error without feedback
    fb = controller(gains, target_m=0.0)
    fb.set_target(target)
    zmp = measured(fb.angle)
    for _ in range(6000):  # 60 s
        zmp = measured(fb.step(zmp))
    assert zmp == pytest.approx(target, abs=1e-5)


def test_gain_rule_from_the_plant() -> None:
    gains = ZmpFeedbackGains.from_plant(0.9, LENGTH_M, output_limit_rad=0.05, g=9.81)
    assert gains.kp_rad_per_m == pytest.approx(0.02 / 0.9)
    assert gains.ki_rad_per_m_s == pytest.approx(0.05 * math.sqrt(9.81 / LENGTH_M) / 0.9)
    assert gains.filter_time_constant_s == pytest.approx(2.0 / math.sqrt(9.81 / LENGTH_M))
    assert gains.integral_limit_rad == gains.output_limit_rad == 0.05


def test_a_robot_that_matches_its_model_gets_no_correction_during_the_lean() -> None:
    """The error is the model's mismatch: a plant that is the model leaves the PI at zero."""
    fb = controller(ZmpFeedbackGains(0.5, 2.0, 0.1, 0.1))
    twin = controller(ZmpFeedbackGains(0.5, 2.0, 0.1, 0.1)).feedforward  # the plan, replayed
    fb.set_target(0.08)
    twin.set_target(0.08)
    schedule = fb.feedforward.schedule
    for _ in range(1500):  # the whole planned lean and its settling
        planned = twin.step()
        angle = fb.step(float(PAPER_A.predict(LENGTH_M * math.sin(planned))))
        assert fb.correction == pytest.approx(0.0, abs=1e-12)
    assert angle == pytest.approx(float(schedule.commanded_angle(0.08)), abs=1e-6)
    assert fb.expected_zmp(angle) == pytest.approx(0.08, abs=1e-9)


def test_the_pi_holds_while_the_plan_moves() -> None:
    fb = controller(ZmpFeedbackGains(0.0, 1.0, 0.1, 0.1, still_angle_rad=0.002))
    fb.set_target(0.08)
    ticks = 0
    while abs(fb.feedforward.angle - fb.feedforward.steady_angle) > 0.002 or ticks == 0:
        fb.step(0.0)  # the robot never moves: a large mismatch all along
        ticks += 1
        if abs(fb.feedforward.angle - fb.feedforward.steady_angle) > 0.002:
            assert fb.integral == 0.0
    assert ticks > 100  # the plan moved for over a second
    for _ in range(100):
        fb.step(0.0)
    assert fb.integral > 0.0  # once the plan is still, the mismatch is integrated


def test_the_same_pi_wraps_the_lipm_whose_model_is_l_sin_theta() -> None:
    lipm = LipmController(
        LENGTH_M, DT_S, angle_limit_rad=ANGLE_LIMIT_RAD, support_polygon=(-0.12, 0.15)
    )
    fb = DlipmFeedbackController(lipm, ZmpFeedbackGains(0.0, 0.5, 0.1, 0.1))
    fb.set_target(0.05)
    feedforward = math.asin(0.05 / LENGTH_M)
    assert fb.expected_zmp(feedforward) == pytest.approx(0.05, rel=1e-12)
    for _ in range(100):  # 1 s of a measured ZMP 10 mm short of the LIPM's
        angle = fb.step(0.04)
    assert fb.integral == pytest.approx(0.5 * 0.01 * 1.0, rel=1e-9)
    assert angle == pytest.approx(feedforward + fb.integral, abs=1e-12)
    pid = PidGains(1.0, 0.0, 0.0, 0.1)
    closed = LipmController(
        LENGTH_M, DT_S, angle_limit_rad=0.3, support_polygon=(-0.1, 0.1), pid=pid
    )
    with pytest.raises(ParameterError, match="open loop"):
        DlipmFeedbackController(closed, ZmpFeedbackGains(0.0, 0.5, 0.1, 0.1))


@settings(max_examples=200, deadline=None)
@given(
    kp=st.floats(0.0, 1e4),
    ki=st.floats(0.0, 1e4),
    limit=st.floats(1e-4, 1.0),
    target=st.floats(-0.12, 0.15),
    samples=st.lists(st.one_of(st.none(), st.floats(-1e6, 1e6)), min_size=1, max_size=60),
)
@pytest.mark.slow
def test_output_always_within_clamps_and_finite(
    kp: float, ki: float, limit: float, target: float, samples: list[float | None]
) -> None:
    fb = controller(ZmpFeedbackGains(kp, ki, limit, limit))
    fb.set_target(target)
    for sample in samples:
        angle = fb.step(sample)
        assert math.isfinite(angle)
        assert abs(angle) <= ANGLE_LIMIT_RAD
        assert abs(fb.correction) <= limit
        assert abs(fb.integral) <= limit


def test_step_does_not_allocate() -> None:
    fb = controller(ZmpFeedbackGains(0.1, 0.3, 0.05, 0.05), target_m=0.0)
    fb.set_target(0.07)
    for _ in range(100):
        fb.step(0.01)

    growth, peak = traced_growth_and_peak(lambda k: fb.step(None if k % 7 == 0 else 0.06), 1000)
    assert growth < 256  # [bytes] no growth over 1000 ticks
    assert peak < 1024


def test_gain_error_texts() -> None:
    with pytest.raises(ParameterError, match="kp_rad_per_m"):
        ZmpFeedbackGains(-1.0, 0.0, 0.1, 0.1)
    with pytest.raises(ParameterError, match="output_limit_rad"):
        ZmpFeedbackGains(1.0, 0.0, 0.1, 0.0)
    with pytest.raises(ParameterError, match="dc_gain_m_per_rad"):
        ZmpFeedbackGains.from_plant(-0.5, LENGTH_M, 0.1)
    fb = controller(ZmpFeedbackGains(1.0, 1.0, 0.1, 0.1))
    with pytest.raises(ParameterError, match="finite"):
        fb.step(math.nan)
