"""Tests of zmpkit.control: the gain surface, the scheduled DLIPM and the LIPM baselines."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.allocations import traced_growth_and_peak
from zmpkit.control import (
    DlipmController,
    GainSchedule,
    LinearCorrectionController,
    LipmController,
    PidGains,
    paper_a_coded_gains,
)
from zmpkit.errors import ModelError, ParameterError
from zmpkit.identify import BalanceParams, ErrorModel, PlaneParams, fit_error_model
from zmpkit.models import Dlipm

PAPER_A = ErrorModel("quadratic", (0.834, 1.024, -0.0004))  # paper A eq. 13
MASS_KG, LENGTH_M, G = 62.6, 0.893, 9.81  # paper A §4.1
DT_S = 0.01
POLYGON_M = (-0.12, 0.15)
MODELS = [
    PAPER_A,
    ErrorModel("odd_quadratic", (-0.6, 1.05, 0.002)),
    ErrorModel("cubic", (-4.0, 0.834, 1.024, -0.0004)),
    ErrorModel("linear", (0.97, 0.0015)),
]


def dlipm_controller(model: ErrorModel = PAPER_A, **limits: float) -> DlipmController:
    schedule = GainSchedule(model, MASS_KG, LENGTH_M)
    return DlipmController(
        schedule,
        DT_S,
        angle_limit_rad=limits.get("angle", 0.3),
        rate_limit_rad_s=limits.get("rate", 2.0),
        support_polygon=POLYGON_M,
    )


def plant_zmp(model: ErrorModel, angle: float) -> float:
    """The synthetic robot: measured ZMP = f(l sin θ) [m]."""
    return float(model.predict(LENGTH_M * math.sin(angle)))


# --- gain surface ----------------------------------------------------------------------------


def test_schedule_matches_the_inverse_and_the_dlipm_design() -> None:
    schedule = GainSchedule(PAPER_A, MASS_KG, LENGTH_M)
    x = np.linspace(-0.1, 0.1, 201)
    np.testing.assert_allclose(
        schedule.theta_offset + schedule.dc_gain(x) * x, schedule.commanded_angle(x), atol=1e-16
    )
    assert schedule.commanded_angle(0.0) == pytest.approx(math.asin(PAPER_A.invert(0.0) / LENGTH_M))
    for target in (-0.07, 0.0, 0.04, 0.1):
        design = Dlipm.design(MASS_KG, LENGTH_M, dc_gain=schedule.dc_gain(target), zeta=0.8)
        model = schedule.dlipm(target)
        assert model.k_a == pytest.approx(design.k_a, rel=1e-14)
        assert model.b_a == pytest.approx(design.b_a, rel=1e-14)
        assert model.dc_gain == pytest.approx(schedule.dc_gain(target), rel=1e-12)
        assert model.zeta == pytest.approx(0.8, rel=1e-12)


def test_gain_at_zero_is_the_derivative_of_the_commanded_angle() -> None:
    schedule = GainSchedule(PAPER_A, MASS_KG, LENGTH_M)
    u0 = PAPER_A.invert(0.0)
    closed_form = 1.0 / (LENGTH_M * math.sqrt(1 - (u0 / LENGTH_M) ** 2) * PAPER_A.derivative(u0))
    assert schedule.dc_gain(0.0) == pytest.approx(closed_form, rel=1e-15)
    h = 1e-5
    central = (schedule.commanded_angle(h) - schedule.commanded_angle(-h)) / (2 * h)
    assert schedule.dc_gain(0.0) == pytest.approx(central, rel=1e-8)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.kind)
def test_gain_surface_is_finite_and_continuous_on_a_dense_grid(model: ErrorModel) -> None:
    schedule = GainSchedule(model, MASS_KG, LENGTH_M)
    x = np.linspace(-0.1, 0.1, 20_001 if model.kind in ("quadratic", "linear") else 2_001)
    step = x[1] - x[0]
    for surface in (schedule.dc_gain(x), schedule.k_a(x), schedule.b_a(x)):
        assert np.all(np.isfinite(surface))
        assert np.all(surface > 0.0)
        # continuous: neighbours differ by at most the steepest slope over the grid times Δx
        slope = np.abs(np.diff(surface)) / step
        assert slope.max() < 20.0 * np.median(slope) + 1e-9


@settings(max_examples=60, deadline=None)
@given(
    a=st.floats(-2.0, 2.0),
    b=st.floats(0.8, 1.2),
    c=st.floats(-0.005, 0.005),
    x=st.floats(-1e-3, 1e-3),
)
def test_gain_tends_to_its_value_at_zero(a: float, b: float, c: float, x: float) -> None:
    schedule = GainSchedule(ErrorModel("quadratic", (a, b, c)), MASS_KG, LENGTH_M)
    k0 = schedule.dc_gain(0.0)
    # K is analytic at 0: |K(x) - K(0)| <= L |x| with L well above |K'| for these models
    assert abs(schedule.dc_gain(x) - k0) <= 10.0 * abs(x)
    assert math.isfinite(schedule.k_a(x))
    assert math.isfinite(schedule.b_a(x))


def test_teo_coded_law_matches_the_table_and_jumps_near_zero() -> None:
    # robots/teo-parameters.md §8, computed from W LIPM2d.cpp
    r = [0.00, 0.02, 0.04, 0.06, 0.08, 0.09, 0.10]
    k_a, b_a = paper_a_coded_gains(r)
    table_k = [9.9500, 9.9580, 9.9671, 9.9754, 9.9837, 9.9879, 9.9921]
    table_b = [46.84, 48.16, 49.62, 50.92, 52.17, 52.79, 53.41]
    np.testing.assert_allclose(k_a, table_k, atol=5e-5)
    np.testing.assert_allclose(b_a, table_b, atol=5e-3)
    # its fallback below r ≈ 0.39 mm makes k_a jump from 9.95 to about g (β → 0)
    grid = np.linspace(-0.001, 0.001, 2001)
    teo_k = paper_a_coded_gains(grid)[0]
    assert np.max(np.abs(np.diff(teo_k))) > 0.1
    assert np.all(teo_k[grid < 0.0] == 9.95)
    ours = GainSchedule(PAPER_A, MASS_KG, LENGTH_M).k_a(grid) / MASS_KG
    assert np.max(np.abs(np.diff(ours))) < 1e-3


def test_schedule_from_params_and_its_errors() -> None:
    params = BalanceParams(MASS_KG, LENGTH_M, {"sagittal": PlaneParams(PAPER_A)})
    schedule = GainSchedule.from_params(params, "sagittal", zeta=0.7)
    assert schedule.zeta == 0.7
    assert schedule.length == LENGTH_M
    with pytest.raises(
        ParameterError, match=r"no parameters for plane 'frontal'; have \('sagittal',\)"
    ):
        GainSchedule.from_params(params, "frontal")
    with pytest.raises(ModelError, match="slope b = -1 <= 0"):
        GainSchedule(ErrorModel("linear", (-1.0, 0.0)), MASS_KG, LENGTH_M)
    with pytest.raises(ModelError, match=r"not below the pendulum length 0\.893 m"):
        GainSchedule(PAPER_A, MASS_KG, LENGTH_M).dc_gain(2.0)  # f⁻¹(2.0) = 1.05 m


# --- scheduled DLIPM -------------------------------------------------------------------------


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.kind)
@pytest.mark.parametrize("target", [-0.05, 0.0, 0.005, 0.03, 0.07, 0.1])
def test_scheduled_dlipm_lands_on_the_target(model: ErrorModel, target: float) -> None:
    controller = dlipm_controller(model)
    controller.set_target(target)
    for _ in range(1500):
        angle = controller.step()
    assert plant_zmp(model, angle) == pytest.approx(target, abs=1e-6)


def test_scheduling_beats_one_linear_correction_and_the_lipm() -> None:
    errors = {}
    kwargs = {"angle_limit_rad": 0.3, "support_polygon": POLYGON_M}
    baselines = {
        "lipm": LipmController(LENGTH_M, DT_S, **kwargs),
        "linear": LinearCorrectionController.from_error_model(PAPER_A, LENGTH_M, DT_S, **kwargs),
    }
    for name, controller in baselines.items():
        controller.set_target(0.1)
        errors[name] = abs(plant_zmp(PAPER_A, controller.step()) - 0.1)
    dlipm = dlipm_controller()
    dlipm.set_target(0.1)
    for _ in range(1500):
        angle = dlipm.step()
    errors["dlipm"] = abs(plant_zmp(PAPER_A, angle) - 0.1)
    # LIPM: f(0.1) - 0.1 = 0.0103 m (10.3 %, paper A Table 1: 11.6 %)
    assert errors["lipm"] == pytest.approx(0.834 * 0.01 + 0.024 * 0.1 - 0.0004, rel=1e-9)
    assert errors["dlipm"] < 1e-6 < errors["linear"] < errors["lipm"]


def test_schedule_fitted_on_even_targets_validates_on_all_targets() -> None:
    """Paper A Table 1 protocol on synthetic steady states: fit on 0, 0.02 … 0.10 m."""
    rng = np.random.default_rng(0)
    even = np.round(np.arange(0.0, 0.1001, 0.02), 2)
    measured = PAPER_A.predict(even) + rng.normal(0.0, 2e-4, even.size)
    fit = fit_error_model(even, measured, model="quadratic")
    schedule = GainSchedule(fit.model, MASS_KG, LENGTH_M)
    targets = np.round(np.arange(0.01, 0.1001, 0.01), 2)
    dlipm = np.abs(PAPER_A.predict(LENGTH_M * np.sin(schedule.steady_angle(targets))) - targets)
    lipm = np.abs(PAPER_A.predict(targets) - targets)
    assert dlipm[-1] <= 0.2 * lipm[-1]
    assert dlipm.mean() <= lipm.mean() / 3.0


def test_target_is_clamped_to_the_support_polygon() -> None:
    controller = dlipm_controller()
    assert controller.set_target(0.5) == POLYGON_M[1]
    assert controller.requested_target == 0.5
    assert controller.target == POLYGON_M[1]
    for _ in range(1500):
        angle = controller.step()
    assert plant_zmp(PAPER_A, angle) == pytest.approx(POLYGON_M[1], abs=1e-6)


@settings(max_examples=25, deadline=None)
@given(targets=st.lists(st.floats(-0.2, 0.2), min_size=1, max_size=6))
def test_step_respects_angle_and_rate_limits(targets: list[float]) -> None:
    angle_limit, rate_limit = 0.08, 0.05
    controller = dlipm_controller(angle=angle_limit, rate=rate_limit)
    previous = controller.angle
    for target in targets:
        controller.set_target(target)
        for _ in range(150):
            angle = controller.step()
            assert abs(angle) <= angle_limit
            assert abs(angle - previous) <= rate_limit * DT_S * (1 + 1e-12)
            previous = angle


def test_angle_is_continuous_when_the_target_changes_mid_motion() -> None:
    controller = dlipm_controller(angle=1.0, rate=100.0)  # limits never act
    controller.set_target(0.1)
    for _ in range(40):  # mid-motion: about half-way and moving fast
        before = controller.step()
    assert controller.rate > 0.05
    controller.set_target(-0.05)
    after = controller.step()
    # one period of the state's own motion, not a jump to the new steady angle (~0.16 rad away)
    assert abs(after - before) < 1.5 * controller.rate * DT_S + 1e-3
    assert abs(controller.steady_angle - before) > 0.1


def test_rate_limited_output_converges_without_windup() -> None:
    controller = dlipm_controller(rate=0.02)
    controller.set_target(0.1)
    angles = [controller.step() for _ in range(2000)]
    step = controller.steady_angle - controller.schedule.theta_offset
    # back-calculation: no more overshoot than the free DLIPM's, exp(-πζ/√(1-ζ²)) = 1.52 % at 0.8
    assert max(angles) - controller.steady_angle < 0.0152 * step
    assert angles[-1] == pytest.approx(controller.steady_angle, abs=1e-9)


def test_step_does_not_allocate() -> None:
    controller = dlipm_controller()
    controller.set_target(0.07)
    for _ in range(100):
        controller.step()
    growth, peak = traced_growth_and_peak(lambda _: controller.step(), 1000)
    assert growth < 256  # [bytes] no growth over 1000 ticks
    assert peak < 1024  # no arrays or containers built per tick


def test_dlipm_controller_error_texts() -> None:
    schedule = GainSchedule(PAPER_A, MASS_KG, LENGTH_M)
    good = {"angle_limit_rad": 0.3, "rate_limit_rad_s": 1.0, "support_polygon": POLYGON_M}
    with pytest.raises(ParameterError, match=r"support_polygon must have x_min < x_max"):
        DlipmController(schedule, DT_S, **{**good, "support_polygon": (0.1, -0.1)})
    with pytest.raises(ParameterError, match=r"angle_limit_rad must be > 0 rad, got -0\.1 rad"):
        DlipmController(schedule, DT_S, **{**good, "angle_limit_rad": -0.1})
    with pytest.raises(ParameterError, match=r"dt must be > 0 s, got 0\.0 s"):
        DlipmController(schedule, 0.0, **good)
    with pytest.raises(ParameterError, match="x_ref must be finite, got nan"):
        DlipmController(schedule, DT_S, **good).set_target(math.nan)


# --- LIPM baselines --------------------------------------------------------------------------


def test_lipm_commands_the_static_pendulum_angle() -> None:
    controller = LipmController(LENGTH_M, DT_S, angle_limit_rad=1.0, support_polygon=(-2.0, 2.0))
    controller.set_target(0.05)
    assert controller.step() == math.asin(0.05 / LENGTH_M)
    with pytest.raises(ParameterError, match=r"must satisfy \|x_cmd\| < l = 0.893 m"):
        controller.set_target(0.95)


def test_lipm_with_pid_removes_the_steady_state_error() -> None:
    pid = PidGains(kp_rad_per_m=0.5, ki_rad_per_m_s=5.0, kd_rad_s_per_m=0.0, output_limit_rad=0.05)
    controller = LipmController(
        LENGTH_M, DT_S, angle_limit_rad=0.3, support_polygon=POLYGON_M, pid=pid
    )
    controller.set_target(0.1)
    measured = None
    for _ in range(3000):
        measured = plant_zmp(PAPER_A, controller.step(measured))
    assert measured == pytest.approx(0.1, abs=1e-6)


def test_pid_anti_windup_recovers_at_once() -> None:
    pid = PidGains(kp_rad_per_m=0.0, ki_rad_per_m_s=10.0, output_limit_rad=0.01)
    controller = LipmController(
        LENGTH_M, DT_S, angle_limit_rad=0.3, support_polygon=POLYGON_M, pid=pid
    )
    controller.set_target(0.0)
    for _ in range(5000):  # a stuck plant: the measured ZMP stays at -0.05 m
        controller.step(-0.05)
    assert controller.angle == pytest.approx(0.01)  # saturated correction
    ticks = 0
    while controller.step(0.05) > 0.0:  # the error reverses
        ticks += 1
    assert ticks <= 3  # with windup it would take 5000 ticks (the integral 10 × 50 s × 0.05 m)


def test_pid_gains_error_texts() -> None:
    with pytest.raises(ParameterError, match=r"kp_rad_per_m must be >= 0, got -1\.0"):
        PidGains(kp_rad_per_m=-1.0)
    with pytest.raises(ParameterError, match=r"output_limit_rad must be > 0 rad"):
        PidGains(kp_rad_per_m=1.0, output_limit_rad=0.0)
    with pytest.raises(ParameterError, match=r"slope must be > 0, got 0\.0"):
        LinearCorrectionController(
            LENGTH_M, DT_S, slope=0.0, offset=0.0, angle_limit_rad=0.3, support_polygon=POLYGON_M
        )


def test_time_scale_slows_the_trajectory_by_exactly_that_factor() -> None:
    """With time_scale s, tick k·s of the scaled DLIPM equals tick k of the SI one."""
    from zmpkit.control import PAPER_A_TIME_SCALE

    schedule = GainSchedule(PAPER_A, MASS_KG, LENGTH_M)
    limits = {"angle_limit_rad": 0.3, "rate_limit_rad_s": 10.0, "support_polygon": POLYGON_M}
    fast = DlipmController(schedule, DT_S, **limits)
    slow = DlipmController(schedule, DT_S / 4, time_scale=4.0, **limits)
    for c in (fast, slow):
        c.reset(schedule.theta_offset)
        c.set_target(0.09)
    fast_angles = [fast.step() for _ in range(200)]
    slow_angles = [slow.step() for _ in range(4 * 4 * 200)]
    np.testing.assert_allclose(slow_angles[15::16], fast_angles, rtol=1e-9, atol=1e-12)
    assert math.isclose(PAPER_A_TIME_SCALE, 7.5694, abs_tol=1e-4)  # √(180/π)


@pytest.mark.parametrize("target", [0.01, 0.05, 0.1])
def test_servo_paced_plan_stays_within_the_acceleration_limit(target: float) -> None:
    """ω_n²|Δθ| ≤ a: the planned angle's acceleration (finite differences) stays below a."""
    schedule = GainSchedule(PAPER_A, MASS_KG, LENGTH_M)
    limit = 0.1  # [rad/s²], TEO's servo acceleration limit
    controller = DlipmController(
        schedule,
        DT_S,
        angle_limit_rad=0.3,
        rate_limit_rad_s=10.0,
        support_polygon=POLYGON_M,
        max_acceleration_rad_s2=limit,
    )
    controller.reset(0.0)
    controller.set_target(target)
    angles = np.array([0.0] + [controller.step() for _ in range(3000)])
    acceleration = np.diff(angles, 2) / DT_S**2
    assert controller.active_time_scale > 1.0
    assert np.max(np.abs(acceleration)) <= limit * 1.01
    assert np.max(np.abs(acceleration)) >= limit * 0.9  # no slower than it needs to be
    assert angles[-1] == pytest.approx(schedule.steady_angle(target), rel=1e-6)


def test_schedule_knows_its_fitted_range_and_extrapolates_beyond_it_unchanged() -> None:
    from zmpkit.control import GainSchedule
    from zmpkit.control.schedule import EXTRAPOLATION_TOLERANCE_M

    fitted = GainSchedule(PAPER_A, 62.6, 0.893, fitted_range=(0.0, 0.08))
    free = GainSchedule(PAPER_A, 62.6, 0.893)
    assert not fitted.extrapolates(0.0)
    assert not fitted.extrapolates(0.08 + 0.5 * EXTRAPOLATION_TOLERANCE_M)
    assert fitted.extrapolates(0.1)
    assert fitted.extrapolates(-0.01)
    assert not free.extrapolates(0.1)  # no range known: nothing flagged
    # the documented rule: beyond the range the fitted polynomial is used as it is
    assert fitted.commanded_zmp(0.1) == free.commanded_zmp(0.1) == PAPER_A.invert(0.1)
