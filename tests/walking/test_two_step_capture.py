"""The two-step capture against the LIPM's closed forms and Koolen et al.'s N-step condition."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.walking.two_step_capture import solve_two_step, solve_two_step_into, two_step_capture

OMEGA = math.sqrt(9.80665 / 0.25)  # a walker with its CoM 0.25 m high [1/s]


def _dcm_after(xi: float, zmp: float, seconds: float) -> float:
    """ξ(t) = p + (ξ_0 - p) e^{ωt} of the LIPM with the ZMP held at ``p`` [m]."""
    return zmp + (xi - zmp) * math.exp(OMEGA * seconds)


def test_captured_two_steps_leave_the_dcm_on_the_second_sole() -> None:
    """Integrating ξ̇ = ω(ξ - p) over both steps puts ξ on p_2 at the second touchdown."""
    reach = 0.25
    result = two_step_capture(
        (0.05, 0.10), OMEGA, 0.15, 0.3, (0.0, 0.0),
        (-reach, reach, -reach, reach), (-reach, reach, -reach, reach),
    )  # fmt: skip
    assert result.captured
    for xi0, p1, u2 in zip((0.05, 0.10), result.first_m, result.second_m, strict=True):
        xi = _dcm_after(_dcm_after(xi0, 0.0, 0.15), p1, 0.3)
        assert xi == pytest.approx(p1 + u2, abs=1e-12)


def test_one_step_suffices_when_the_first_box_holds_the_dcm() -> None:
    """A DCM the first step reaches is captured with u_2 = 0 if the plan's landing allows it."""
    sigma = math.exp(OMEGA * 0.2)
    first, second, left = solve_two_step(
        0.02, sigma, 2.0, 0.02 * sigma, -0.3, 0.3, -0.3, 0.3, 0.0, 0.0
    )
    assert (first, second, left) == pytest.approx((0.02 * sigma, 0.0, 0.0), abs=1e-12)


@settings(max_examples=300, deadline=None)
@given(
    x0=st.floats(-0.3, 0.3),
    tau=st.floats(0.0, 0.4),
    duration=st.floats(0.05, 0.6),
    reach=st.floats(0.02, 0.4),
    plan=st.floats(-1.0, 1.0),
)
def test_capturable_iff_koolen_two_step_condition(
    x0: float, tau: float, duration: float, reach: float, plan: float
) -> None:
    """m = l = 0, boxes ±R: captured iff |x_0| σ_1 <= R (1 + 1/σ_2); landings stay in the boxes."""
    s1, s2 = math.exp(OMEGA * tau), math.exp(OMEGA * duration)
    first, second, left = solve_two_step(x0, s1, s2, plan, -reach, reach, -reach, reach, 0.0, 0.0)
    bound = reach * (1.0 + 1.0 / s2)
    assert -reach <= first <= reach
    assert -reach <= second <= reach
    if abs(abs(x0) * s1 - bound) > 1e-9:
        assert (left == 0.0) == (abs(x0) * s1 < bound)
    if left > 0.0:  # not captured: the closed-form miss of the furthest landings
        assert left == pytest.approx((abs(x0) * s1 - reach) * s2 - reach, abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(
    x0=st.floats(-0.3, 0.3),
    tau=st.floats(0.0, 0.4),
    margin=st.floats(0.0, 0.05),
    landing=st.floats(0.0, 0.03),
)
def test_ankle_and_landing_margins_only_widen_what_is_captured(
    x0: float, tau: float, margin: float, landing: float
) -> None:
    """A case captured without margins stays captured with them (the dead bands only help)."""
    s1, s2 = math.exp(OMEGA * tau), math.exp(OMEGA * 0.3)
    bare = solve_two_step(x0, s1, s2, 0.0, -0.1, 0.1, -0.1, 0.1, 0.0, 0.0)[2]
    wide = solve_two_step(x0, s1, s2, 0.0, -0.1, 0.1, -0.1, 0.1, margin, landing)[2]
    assert wide <= bare + 1e-12


def test_crossing_limit_box_excluding_zero_is_honoured() -> None:
    """A lateral box [w, R] (no crossing) keeps the legs apart; the miss is the closed form's."""
    s1, s2 = math.exp(OMEGA * 0.1), math.exp(OMEGA * 0.3)
    first, second, left = solve_two_step(-0.01, s1, s2, 0.1, 0.08, 0.3, -0.3, -0.08, 0.0, 0.0)
    assert first == 0.08  # the no-crossing bound, nearest the inward DCM
    assert second == -0.3
    assert left == pytest.approx(abs((-0.01 * s1 - 0.08) * s2 + 0.3), abs=1e-12)


def test_bad_box_is_refused_with_its_value() -> None:
    """A box with lo > hi is refused, naming the box."""
    with pytest.raises(ParameterError, match="first_box_m"):
        two_step_capture(
            (0.0, 0.0), OMEGA, 0.1, 0.3, (0.0, 0.0), (0.1, -0.1, 0.0, 0.0), (0, 0, 0, 0)
        )


@settings(max_examples=200, deadline=None)
@given(
    x0=st.floats(-0.3, 0.3), t1=st.floats(0.0, 0.4), t2=st.floats(0.1, 0.6),
    planned=st.floats(-0.1, 0.1), margin=st.floats(0.0, 0.05),
)  # fmt: skip
def test_the_tick_form_writes_what_the_function_returns(
    x0: float, t1: float, t2: float, planned: float, margin: float
) -> None:
    """:func:`solve_two_step_into` (the control tick's, no tuple) equals :func:`solve_two_step`."""
    args = (x0, math.exp(6.26 * t1), math.exp(6.26 * t2), planned, -0.15, 0.15, -0.25, 0.25,
            margin, 0.0)  # fmt: skip
    out = [0.0, 0.0, 0.0]
    solve_two_step_into(out, *args)
    assert tuple(out) == solve_two_step(*args)
