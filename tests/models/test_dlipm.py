"""Tests of zmpkit.models.dlipm: parameters, design, units, exact responses, errors."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ModelError, ParameterError
from zmpkit.models.dlipm import Dlipm, paper_units_omega_n

TEO_MASS_KG = 62.6  # paper A §4.1
TEO_LENGTH_M = 0.893  # paper A §4.1

# Hand-computed: m = 2 kg, l = 0.5 m, g = 10 m/s², k_a = 40 N, B_a = 6 N·s
# γ = 10 / 0.25 = 40, α = 6 / (2·0.5) = 6, β = (40 − 20) / (2·0.5) = 20, K_DC = 2.
HAND = Dlipm(mass=2.0, length=0.5, k_a=40.0, b_a=6.0, g=10.0)


def test_coefficients_against_hand_computed_values() -> None:
    assert HAND.gamma == pytest.approx(40.0, rel=1e-15)
    assert HAND.alpha == pytest.approx(6.0, rel=1e-15)
    assert HAND.beta == pytest.approx(20.0, rel=1e-15)
    assert HAND.dc_gain == pytest.approx(2.0, rel=1e-15)
    assert HAND.omega_n == pytest.approx(math.sqrt(20.0), rel=1e-15)
    assert HAND.zeta == pytest.approx(6.0 / (2.0 * math.sqrt(20.0)), rel=1e-15)
    assert HAND.is_stable
    assert HAND.require_stable() is HAND


def test_lipm_limit_is_unstable_with_beta_minus_g_over_l() -> None:
    lipm = Dlipm.lipm(TEO_MASS_KG, TEO_LENGTH_M)
    assert lipm.beta == pytest.approx(-9.81 / TEO_LENGTH_M, rel=1e-15)
    assert lipm.alpha == 0.0
    assert lipm.dc_gain == pytest.approx(-1.0 / TEO_LENGTH_M, rel=1e-15)
    assert not lipm.is_stable
    poles = np.sort(lipm.transfer_function().poles().real)
    np.testing.assert_allclose(
        poles, np.array([-1.0, 1.0]) * math.sqrt(9.81 / TEO_LENGTH_M), rtol=1e-12
    )


def test_transfer_function_poles_are_roots_of_the_characteristic_polynomial() -> None:
    tf = HAND.transfer_function()
    roots = np.roots([1.0, HAND.alpha, HAND.beta])
    np.testing.assert_allclose(np.sort_complex(tf.poles()), np.sort_complex(roots), rtol=1e-12)
    np.testing.assert_allclose(
        np.sort_complex(HAND.state_space().poles()), np.sort_complex(roots), rtol=1e-12
    )
    assert float(np.real(tf.dcgain())) == pytest.approx(HAND.dc_gain, rel=1e-12)


def test_state_space_equals_transfer_function() -> None:
    ss_tf = control.ss2tf(HAND.state_space().to_control())
    np.testing.assert_allclose(np.squeeze(ss_tf.num[0][0])[-1], HAND.gamma, rtol=1e-12)
    np.testing.assert_allclose(np.squeeze(ss_tf.den[0][0]), [1.0, 6.0, 20.0], rtol=1e-12)


@settings(max_examples=60, deadline=None)
@given(
    mass=st.floats(1.0, 200.0),
    length=st.floats(0.2, 2.0),
    dc_gain=st.floats(0.1, 100.0),
    zeta=st.floats(0.0, 2.0),
)
def test_design_round_trip(mass: float, length: float, dc_gain: float, zeta: float) -> None:
    model = Dlipm.design(mass, length, dc_gain=dc_gain, zeta=zeta)
    assert model.dc_gain == pytest.approx(dc_gain, rel=1e-9)
    assert model.zeta == pytest.approx(zeta, rel=1e-9, abs=1e-12)
    assert model.omega_n == pytest.approx(math.sqrt(9.81 / length**2 / dc_gain), rel=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    mass=st.floats(1.0, 200.0),
    k_a_per_kg=st.floats(-20.0, 50.0),
    b_a=st.floats(0.0, 500.0),
)
def test_per_unit_mass_round_trip(mass: float, k_a_per_kg: float, b_a: float) -> None:
    model = Dlipm.from_per_unit_mass(mass, 0.893, k_a_per_kg, b_a)
    assert model.k_a_per_kg == pytest.approx(k_a_per_kg, rel=1e-14, abs=1e-14)
    assert model.b_a == b_a
    # paper A eq. 11 in its own units: β = (k_a' − g)/l, α = B_a/(m l)
    assert model.beta == pytest.approx((k_a_per_kg - 9.81) / 0.893, rel=1e-12, abs=1e-12)
    assert model.alpha == pytest.approx(b_a / (mass * 0.893), rel=1e-14)


def test_teo_code_constants_in_paper_units() -> None:
    # WBPCwaiter LIPM2d.cpp (shared/robots/teo-parameters.md §8): k_a 9.9971, B_a 51.1582
    model = Dlipm.from_per_unit_mass(62.589, 0.8927, 9.9971, 51.1582)
    assert model.k_a == pytest.approx(62.589 * 9.9971, rel=1e-14)
    assert model.beta == pytest.approx((9.9971 - 9.81) / 0.8927, rel=1e-12)
    assert model.is_stable


def test_si_dc_gain_matching_design_has_omega_n_sqrt_g_over_l() -> None:
    model = Dlipm.design(TEO_MASS_KG, TEO_LENGTH_M, dc_gain=1.0 / TEO_LENGTH_M, zeta=0.8)
    assert model.omega_n == pytest.approx(math.sqrt(9.81 / 0.893), rel=1e-12)
    assert model.omega_n == pytest.approx(3.3144, abs=5e-5)
    assert model.k_a == pytest.approx(2.0 * TEO_MASS_KG * 9.81, rel=1e-12)  # β = g/l


def test_paper_design_omega_n_is_the_degree_dc_gain_design() -> None:
    degrees_per_m = math.degrees(1.0) / TEO_LENGTH_M
    model = Dlipm.design(TEO_MASS_KG, TEO_LENGTH_M, dc_gain=degrees_per_m, zeta=0.8)
    assert model.omega_n == pytest.approx(paper_units_omega_n(TEO_LENGTH_M), rel=1e-12)
    assert paper_units_omega_n(TEO_LENGTH_M) == pytest.approx(0.43787, abs=5e-6)
    assert round(paper_units_omega_n(TEO_LENGTH_M, g=9.8), 4) == 0.4376  # paper A §4.4


def _analytic_underdamped_step(model: Dlipm, t: np.ndarray, amplitude: float) -> np.ndarray:
    wn, z = model.omega_n, model.zeta
    wd = wn * math.sqrt(1.0 - z * z)
    decay = np.exp(-z * wn * t)
    shape = 1.0 - decay * (np.cos(wd * t) + z / math.sqrt(1.0 - z * z) * np.sin(wd * t))
    return amplitude * model.dc_gain * shape


def test_step_response_is_the_analytic_solution_on_any_grid() -> None:
    model = Dlipm.design(TEO_MASS_KG, TEO_LENGTH_M, dc_gain=1.2, zeta=0.3)
    t = np.sort(np.random.default_rng(0).uniform(0.0, 4.0, 80))
    response = model.step_response(t, 0.09)
    np.testing.assert_allclose(
        response.theta, _analytic_underdamped_step(model, t, 0.09), rtol=1e-9, atol=1e-13
    )


def test_step_response_matches_python_control_on_a_uniform_grid() -> None:
    model = Dlipm.design(TEO_MASS_KG, TEO_LENGTH_M, dc_gain=1.1, zeta=0.8)
    t = np.linspace(0.0, 3.0, 301)
    ours = model.step_response(t, -0.05)
    theirs = control.step_response(model.transfer_function() * -0.05, t)
    np.testing.assert_allclose(ours.theta, theirs.outputs, rtol=1e-9, atol=1e-13)


@pytest.mark.parametrize("zeta", [0.5, 1.0, 1.5])
def test_step_response_final_value_is_amplitude_times_dc_gain(zeta: float) -> None:
    model = Dlipm.design(TEO_MASS_KG, TEO_LENGTH_M, dc_gain=1.3, zeta=zeta)
    response = model.step_response(np.linspace(0.0, 40.0, 401), 0.07)
    assert response.theta[-1] == pytest.approx(0.07 * model.dc_gain, rel=1e-9)
    assert response.theta_dot[-1] == pytest.approx(0.0, abs=1e-9)
    assert response.amplitude_m == 0.07


def test_discretize_is_zoh_of_the_state_space() -> None:
    disc = HAND.discretize(0.03)
    response = HAND.step_response(0.03 * np.arange(21), 0.1)
    x, _ = disc.simulate(np.full(20, 0.1))
    np.testing.assert_allclose(x[:, 0], response.theta, rtol=1e-10, atol=1e-14)


def test_require_stable_names_beta_and_the_bound_on_k_a() -> None:
    lipm = Dlipm.lipm(TEO_MASS_KG, TEO_LENGTH_M)
    expected = (
        "the DLIPM is unstable: beta = (k_a - m·g)/(m·l) = -10.9854 1/s^2 <= 0; "
        "k_a must exceed m·g = 614.106 N, got k_a = 0 N"
    )
    with pytest.raises(ModelError) as info:
        lipm.require_stable()
    assert str(info.value) == expected


def test_require_stable_rejects_missing_damping() -> None:
    undamped = Dlipm(2.0, 0.5, k_a=40.0, b_a=0.0, g=10.0)
    with pytest.raises(ModelError, match=r"alpha = B_a/\(m·l\) = 0 1/s <= 0; B_a must be > 0"):
        undamped.require_stable()


def test_dc_gain_undefined_when_beta_is_zero() -> None:
    with pytest.raises(ModelError, match=r"DC gain gamma/beta is undefined: beta = 0"):
        _ = Dlipm(2.0, 0.5, k_a=20.0, b_a=1.0, g=10.0).dc_gain


def test_omega_n_undefined_when_beta_is_negative() -> None:
    with pytest.raises(ModelError, match=r"omega_n = sqrt\(beta\) needs beta > 0, got beta = -20"):
        _ = Dlipm.lipm(2.0, 0.5, g=10.0).omega_n


def test_negative_mass_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"mass must be > 0 kg, got -62.6 kg"):
        Dlipm(-62.6, 0.893, 1000.0, 100.0)


def test_zero_length_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"length must be > 0 m, got 0.0 m"):
        Dlipm(62.6, 0.0, 1000.0, 100.0)


def test_nan_spring_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"k_a must be finite, got nan"):
        Dlipm(62.6, 0.893, float("nan"), 100.0)


def test_design_rejects_non_positive_dc_gain_and_negative_zeta() -> None:
    with pytest.raises(ParameterError, match=r"dc_gain must be > 0 rad/m, got -1.0 rad/m"):
        Dlipm.design(62.6, 0.893, dc_gain=-1.0, zeta=0.8)
    with pytest.raises(ParameterError, match=r"zeta must be >= 0, got -0.1"):
        Dlipm.design(62.6, 0.893, dc_gain=1.0, zeta=-0.1)


def test_step_response_rejects_times_before_the_step() -> None:
    with pytest.raises(ParameterError, match=r"t must start at or after the step at t = 0 s"):
        HAND.step_response([-0.1, 0.0, 0.1], 0.1)
