"""The DCM stabiliser against closed forms, on a robot that follows its CoM command exactly.

The robot of these tests is the observer's own model: its CoM is the commanded one
(``c^{ref} + Δc``) plus a chosen displacement ``δ``, its ZMP the commanded cart table's
(``c_{cmd} - z_c/g\\,\\ddot c_{cmd}``) plus ``δ`` and a chosen ZMP error ``d_0``. The steady
states then follow from the module docstring by hand:

- ``δ = d_0 = 0``: nothing to correct, ``Δc ≡ 0``;
- a displacement ``δ``: the DCM error is ``Δc + δ`` and the admittance's ZMP error the same,
  so ``Δc → -δ`` (the CoM is brought back to the plan);
- a ZMP error ``d_0`` alone: the observer sees no CoM error (its offset takes ``d_0``), the
  admittance pushes ``A'_c (Δc + d_0)`` against the DCM term's ``ω K_ξ Δc``, so
  ``Δc → A'_c d_0 / (ω K_ξ - A'_c)`` with ``A'_c = A_c ω²/(ω² + A_c)`` (0 without
  admittance).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.walking.dcm_parameters import (
    DcmParameters,
    follower_spectral_radius,
    follower_transition,
)
from zmpkit.walking.dcm_stabiliser import DcmStabiliser

G = 9.80665
Z_C = 0.25
T = 0.01
OMEGA = math.sqrt(G / Z_C)


def stable(gain: float, admittance: float) -> DcmParameters:
    """Parameters with these gains, the case skipped where the loop is unstable."""
    parameters = DcmParameters(dcm_gain_per_s=gain, com_admittance_per_s2=admittance)
    assume(follower_spectral_radius(parameters, Z_C, T, G) < 1.0)
    return parameters


def settling_periods(parameters: DcmParameters) -> int:
    """Periods for the loop's slowest mode to fall by e^-20 [-].

    The loop's (:func:`follower_transition`, the observer's modes included: its offset's
    τ ≈ 4.2 s at the least); near the stability bound the loop is slower still, and cases
    slower than a 0.999 radius (about 200 s to settle) are skipped.
    """
    radius = follower_spectral_radius(parameters, Z_C, T, G)
    assume(radius < 0.999)
    return math.ceil(20.0 / -math.log(radius))


def plan(
    n: int, amplitude_m: float, frequency_hz: float, speed_mps: float
) -> tuple[NDArray[np.float64], ...]:
    """A swaying, advancing CoM plan and its exact cart-table ZMP, both axes alike."""
    t = np.arange(n) * T
    w = 2.0 * math.pi * frequency_hz
    c = amplitude_m * np.sin(w * t) + speed_mps * t
    v = amplitude_m * w * np.cos(w * t) + speed_mps
    a = -amplitude_m * w * w * np.sin(w * t)
    both = [np.column_stack([x, x]) for x in (c, v, a)]
    return both[0], both[1], both[2], both[0] - Z_C / G * both[2]


def follow(
    stabiliser: DcmStabiliser,
    com: NDArray[np.float64],
    acceleration: NDArray[np.float64],
    displacement_m: float,
    zmp_error_m: float,
    nan_zmp: bool = False,
) -> NDArray[np.float64]:
    """Run the stabiliser on the ideal follower; Δc after every period [m], shape (N, 2)."""
    shifts = np.zeros_like(com)
    for k in range(com.shape[0]):
        c_cmd = com[k] + stabiliser.shift_in_world
        a_cmd = acceleration[k] + stabiliser.shift_acceleration_in_world
        measured_com = c_cmd + displacement_m
        measured_zmp = c_cmd - Z_C / G * a_cmd + displacement_m + zmp_error_m
        if nan_zmp:
            measured_zmp = np.full(2, np.nan)
        shifts[k] = stabiliser.update(k, measured_com, measured_zmp)
    return shifts


def make(
    c: NDArray[np.float64],
    v: NDArray[np.float64],
    a: NDArray[np.float64],
    p: NDArray[np.float64],
    parameters: DcmParameters,
) -> DcmStabiliser:
    return DcmStabiliser(c, v, a, p, Z_C, T, G, parameters)


@settings(max_examples=25, deadline=None)
@given(
    amplitude=st.floats(0.0, 0.05),
    frequency=st.floats(0.2, 2.0),
    speed=st.floats(-0.3, 0.3),
    gain=st.floats(1.0, 10.0),
    admittance=st.floats(0.0, 30.0),
)
def test_a_robot_on_its_plan_gets_no_correction(
    amplitude: float, frequency: float, speed: float, gain: float, admittance: float
) -> None:
    c, v, a, p = plan(300, amplitude, frequency, speed)
    parameters = stable(gain, admittance)
    stabiliser = make(c, v, a, p, parameters)
    shifts = follow(stabiliser, c, a, 0.0, 0.0)
    assert np.max(np.abs(shifts)) < 1e-12
    assert np.max(np.abs(stabiliser.dcm_error_in_world)) < 1e-12
    np.testing.assert_allclose(stabiliser.desired_zmp_in_world, p, atol=1e-12)


@settings(max_examples=20, deadline=None)
@given(
    displacement=st.floats(-0.02, 0.02),
    gain=st.floats(2.0, 8.0),
    admittance=st.floats(0.0, 30.0),
)
@pytest.mark.slow
def test_a_displaced_robot_is_brought_back_to_its_plan(
    displacement: float, gain: float, admittance: float
) -> None:
    parameters = stable(gain, admittance)
    c, v, a, p = plan(settling_periods(parameters), 0.0, 1.0, 0.0)  # standing
    stabiliser = make(c, v, a, p, parameters)
    shifts = follow(stabiliser, c, a, displacement, 0.0)
    np.testing.assert_allclose(shifts[-1], [-displacement, -displacement], atol=1e-6)
    np.testing.assert_allclose(stabiliser.error_state[:, 0], displacement, atol=1e-6)
    np.testing.assert_allclose(stabiliser.dcm_error_in_world[-1], 0.0, atol=1e-6)


@settings(max_examples=20, deadline=None)
@given(
    zmp_error=st.floats(-0.002, 0.002),
    gain=st.floats(3.0, 8.0),
    admittance=st.floats(0.0, 30.0),
)
@pytest.mark.slow
def test_a_steady_zmp_error_settles_where_the_closed_form_says(
    zmp_error: float, gain: float, admittance: float
) -> None:
    effective = admittance * OMEGA**2 / (OMEGA**2 + admittance)  # A'_c
    parameters = stable(gain, admittance)
    c, v, a, p = plan(settling_periods(parameters), 0.0, 1.0, 0.0)
    stabiliser = make(c, v, a, p, parameters)
    shifts = follow(stabiliser, c, a, 0.0, zmp_error)
    expected = effective * zmp_error / (OMEGA * gain - effective)
    np.testing.assert_allclose(shifts[-1], [expected, expected], atol=1e-7)
    np.testing.assert_allclose(stabiliser.error_state[:, 3], zmp_error, atol=1e-7)
    np.testing.assert_allclose(stabiliser.error_state[:, 0], 0.0, atol=1e-7)


def test_without_a_zmp_reading_nothing_is_corrected_and_nothing_is_nan() -> None:
    c, v, a, p = plan(200, 0.02, 1.0, 0.1)
    stabiliser = make(c, v, a, p, DcmParameters())
    shifts = follow(stabiliser, c, a, 0.0, 0.0, nan_zmp=True)
    assert np.all(np.isfinite(shifts))
    assert np.max(np.abs(shifts)) < 1e-12


def test_the_correction_and_the_asked_zmp_stay_within_their_limits() -> None:
    c, v, a, p = plan(1000, 0.0, 1.0, 0.0)
    parameters = DcmParameters(max_com_shift_m=0.01, max_zmp_shift_m=0.02)
    stabiliser = make(c, v, a, p, parameters)
    shifts = follow(stabiliser, c, a, 0.05, 0.0)  # 5 cm off: more than the CoM may move
    assert np.max(np.abs(shifts)) <= 0.01 + 1e-15
    assert np.max(np.abs(stabiliser.desired_zmp_in_world - p)) <= 0.02 + 1e-12
    np.testing.assert_allclose(shifts[-1], [-0.01, -0.01])


@settings(max_examples=15, deadline=None)
@given(
    gain=st.floats(0.5, 12.0),
    admittance=st.floats(0.0, 40.0),
    integral_gain=st.sampled_from([0.0, 0.5]),
    start=st.lists(st.floats(-0.01, 0.01), min_size=4, max_size=4),
)
def test_the_loop_matrix_is_the_stabiliser_s_own_update(
    gain: float, admittance: float, integral_gain: float, start: list[float]
) -> None:
    """The transition the stability check uses, against the update run on the follower."""
    parameters = DcmParameters(
        dcm_gain_per_s=gain, com_admittance_per_s2=admittance,
        dcm_integral_gain_per_s=integral_gain, max_com_shift_m=1e3, max_zmp_shift_m=1e3,
        integral_limit_m_s=1e3,
    )  # fmt: skip
    assume(follower_spectral_radius(parameters, Z_C, T, G) < 1.0)
    transition = follower_transition(parameters, Z_C, T, G)
    c, v, a, p = plan(40, 0.0, 1.0, 0.0)
    stabiliser = make(c, v, a, p, parameters)
    stabiliser.error_state[0] = start  # an error the observer has yet to learn
    size = transition.shape[0]

    def state() -> NDArray[np.float64]:
        x = [*stabiliser.error_state[0], stabiliser.shift_in_world[0],
             stabiliser.shift_rate_in_world[0], stabiliser.shift_acceleration_in_world[0],
             stabiliser._integral[0]]  # fmt: skip
        return np.array(x[:size])

    x = state()
    for k in range(c.shape[0]):
        c_cmd = c[k] + stabiliser.shift_in_world
        a_cmd = a[k] + stabiliser.shift_acceleration_in_world
        stabiliser.update(k, c_cmd, c_cmd - Z_C / G * a_cmd)
        x = transition @ x
        np.testing.assert_allclose(state(), x, atol=1e-12)


def test_gains_that_ring_on_a_following_robot_are_refused_naming_the_radius() -> None:
    c, v, a, p = plan(10, 0.0, 1.0, 0.0)
    ringing = DcmParameters(dcm_gain_per_s=4.0, com_admittance_per_s2=36.0)
    assert follower_spectral_radius(ringing, Z_C, T, G) > 1.0
    with pytest.raises(ParameterError, match=r"spectral radius 1\.\d{4} >= 1"):
        make(c, v, a, p, ringing)
    make(c, v, a, p, DcmParameters(dcm_gain_per_s=4.0, com_admittance_per_s2=35.0))
    with pytest.raises(ParameterError, match="dcm_gain_per_s must be <= 50"):
        DcmParameters(dcm_gain_per_s=60.0)
