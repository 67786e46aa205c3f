"""The capture step against the LIPM's closed forms, and its limits over random inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.walking.capture_step import (
    capture_step,
    double_support_factor,
    solve_capture,
    transfer_dcm,
    transfer_zmp,
)

OMEGA = math.sqrt(9.80665 / 0.25)  # the built-in walker's ω [1/s]
WIDE = (-1.0, 1.0, -1.0, 1.0)  # a box that never binds [m]


def _lipm_dcm(xi0: float, zmp: float, seconds: float) -> float:
    """ξ(t) of the LIPM with the ZMP held at ``zmp``: ``zmp + (ξ_0 - zmp) e^{ωt}`` [m]."""
    return zmp + (xi0 - zmp) * math.exp(OMEGA * seconds)


def test_a_dcm_on_its_plan_needs_no_change() -> None:
    step = capture_step((0.0, 0.0), (0.01, -0.02), OMEGA, 0.3, 0.1, 0.1, (0.0, 0.0), WIDE)
    assert step.shift_m == (0.0, 0.0)
    assert step.remaining_s == pytest.approx(0.3)
    assert step.captured
    assert step.dcm_error_left_m == 0.0


@pytest.mark.parametrize("error", [(0.03, 0.0), (0.0, -0.02), (-0.01, 0.015)])
def test_a_displaced_dcm_moves_the_landing_by_the_error_carried_to_touchdown(error) -> None:
    """Without double support: Δ = e e^{ωτ}, the LIPM's DCM error at touchdown."""
    tau = 0.25
    step = capture_step(error, (0.004, 0.0), OMEGA, tau, tau, 0.0, (0.0, 0.0), WIDE)
    for axis in (0, 1):
        carried = _lipm_dcm(error[axis], 0.0, tau) - _lipm_dcm(0.0, 0.0, tau)
        assert step.shift_m[axis] == pytest.approx(error[axis] * math.exp(OMEGA * tau))
        assert step.shift_m[axis] == pytest.approx(carried)


def test_the_double_support_transfer_asks_for_the_error_over_kappa() -> None:
    tau, t_d, error = 0.2, 0.1, 0.02
    step = capture_step((error, 0.0), (0.0, 0.0), OMEGA, tau, tau, t_d, (0.0, 0.0), WIDE)
    kappa = (1.0 - math.exp(-OMEGA * t_d)) / (OMEGA * t_d)
    assert double_support_factor(OMEGA, t_d) == pytest.approx(kappa)
    assert step.shift_m[0] == pytest.approx(error * math.exp(OMEGA * tau) / kappa)


def test_the_ankle_margin_is_a_dead_band_that_grows_with_the_time_left() -> None:
    """With the stance CoP shifted by m, ξ(T) = p + (ξ - p) e^{ωτ}: m (e^{ωτ} - 1) is held."""
    tau, margin = 0.3, 0.02
    sigma = math.exp(OMEGA * tau)
    held = margin * (1.0 - 1.0 / sigma)  # the largest error the ankle alone captures [m]
    inside = capture_step((0.99 * held, 0.0), (0.0, 0.0), OMEGA, tau, tau, 0.0, (margin, 0.0), WIDE)
    assert inside.shift_m == (0.0, 0.0)
    error = 0.05
    outside = capture_step((error, 0.0), (0.0, 0.0), OMEGA, tau, tau, 0.0, (margin, 0.0), WIDE)
    # the plan's DCM stays on its ZMP (b = 0): the landing moves by the DCM at touchdown
    assert outside.shift_m[0] == pytest.approx(_lipm_dcm(error, margin, tau))


def test_a_shorter_step_is_taken_when_the_planned_one_cannot_reach() -> None:
    """The latest touchdown whose landing lies in the box: at it, the box's edge exactly."""
    error, tau0, hi = 0.03, 0.35, 0.12
    box = (-hi, hi, -hi, hi)
    step = capture_step((error, 0.0), (0.0, 0.0), OMEGA, tau0, 0.1, 0.0, (0.0, 0.0), box)
    assert step.captured
    assert step.remaining_s == pytest.approx(math.log(hi / error) / OMEGA)
    assert step.shift_m[0] == pytest.approx(hi)


def test_no_admissible_step_is_said_so_and_clipped_to_the_box() -> None:
    box = (-0.05, 0.05, -0.01, 0.06)
    step = capture_step((0.0, -0.06), (0.0, 0.0), OMEGA, 0.3, 0.1, 0.1, (0.0, 0.0), box)
    assert not step.captured
    assert step.shift_m[1] == pytest.approx(-0.01)  # the inner edge: no crossing
    assert step.remaining_s == pytest.approx(0.1)  # the earliest touchdown leaves the least
    needed = -0.06 * math.exp(OMEGA * 0.1) / double_support_factor(OMEGA, 0.1)
    assert step.dcm_error_left_m == pytest.approx(
        double_support_factor(OMEGA, 0.1) * (-0.01 - needed)
    )


def test_a_box_without_the_planned_landing_is_refused() -> None:
    with pytest.raises(ParameterError, match="planned landing"):
        capture_step((0.0, 0.0), (0.0, 0.0), OMEGA, 0.3, 0.1, 0.1, (0.0, 0.0), (0.01, 0.1, -1, 1))


@pytest.mark.parametrize("ahead", [-0.15, -0.1, -0.07, -0.03, 0.0, 0.05, 0.2])
def test_the_dcm_of_a_transfer_is_the_lipm_s_bounded_solution(ahead: float) -> None:
    """ξ(0) = ω ∫_0^∞ e^{-ωs} p(s) ds for the unit ramp starting ``ahead`` [s] from now."""
    t_d = 0.1

    def weighted(s: float) -> float:
        return OMEGA * math.exp(-OMEGA * s) * transfer_zmp(t_d, ahead - s)

    value, _ = scipy.integrate.quad(weighted, 0.0, 10.0, points=[max(ahead, 0.0), ahead + t_d])
    assert transfer_dcm(OMEGA, t_d, ahead) == pytest.approx(value, abs=1e-9)


_error = st.floats(-0.15, 0.15)
_offset = st.floats(-0.08, 0.08)
_lo = st.floats(-0.3, 0.0)
_hi = st.floats(0.0, 0.3)


@settings(max_examples=300, deadline=None)
@given(
    error=st.tuples(_error, _error),
    offset=st.tuples(_offset, _offset),
    tau0=st.floats(0.0, 0.5),
    share=st.floats(0.0, 1.0),
    t_d=st.floats(0.0, 0.2),
    margin=st.tuples(st.floats(0.0, 0.06), st.floats(0.0, 0.06)),
    landing=st.tuples(st.floats(0.0, 0.04), st.floats(0.0, 0.04)),
    box=st.tuples(_lo, _hi, _lo, _hi),
)
def test_the_step_stays_in_its_limits_and_captures_when_it_says_so(
    error, offset, tau0, share, t_d, margin, landing, box
) -> None:
    tau_min = share * tau0
    step = capture_step(error, offset, OMEGA, tau0, tau_min, t_d, margin, box, landing)
    lo_x, hi_x, lo_y, hi_y = box
    assert lo_x <= step.shift_m[0] <= hi_x
    assert lo_y <= step.shift_m[1] <= hi_y
    assert tau_min - 1e-9 <= step.remaining_s <= tau0 + 1e-9
    assert step.dcm_error_left_m >= 0.0
    if step.captured:  # the landing is the one the capture asks for, not a clipped one
        sigma0, sigma = math.exp(OMEGA * tau0), math.exp(OMEGA * step.remaining_s)
        kappa = double_support_factor(OMEGA, t_d)
        for axis in (0, 1):
            d = (error[axis] + offset[axis]) * sigma - offset[axis] * sigma0
            band = margin[axis] * (sigma - 1.0) + landing[axis]
            asked = np.sign(d) * max(abs(d) - band, 0.0) / kappa
            assert step.shift_m[axis] == pytest.approx(asked, abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(error=st.tuples(_error, _error), box=st.tuples(_lo, _hi, _lo, _hi))
def test_the_planned_timing_is_kept_whenever_it_captures(error, box) -> None:
    sigma0, sigma_min, kappa = math.exp(OMEGA * 0.3), math.exp(OMEGA * 0.1), 0.75
    sigma, _, _, left = solve_capture(
        *error, 0.0, 0.0, sigma0, sigma_min, kappa, 0.0, 0.0, 0.0, 0.0, *box
    )
    at_plan = (error[0] * sigma0 / kappa, error[1] * sigma0 / kappa)
    fits = box[0] <= at_plan[0] <= box[1] and box[2] <= at_plan[1] <= box[3]
    if fits:
        assert sigma == sigma0
        assert left == 0.0
    else:
        assert sigma < sigma0 or left > 0.0
