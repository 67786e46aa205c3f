"""Tests of zmpkit.models.lti: exact ZOH discretisation, simulation, validation."""

from __future__ import annotations

import control
import numpy as np
import pytest
from scipy.integrate import quad_vec
from scipy.linalg import expm

from zmpkit.errors import ParameterError
from zmpkit.models.lti import DiscreteLinearSystem, LinearSystem, zero_order_hold


def _random_system(seed: int, n: int, m: int, p: int) -> LinearSystem:
    rng = np.random.default_rng(seed)
    return LinearSystem(
        rng.normal(size=(n, n)),
        rng.normal(size=(n, m)),
        rng.normal(size=(p, n)),
        rng.normal(size=(p, m)),
    )


@pytest.mark.parametrize(
    ("seed", "n", "m", "dt"), [(0, 1, 1, 0.1), (1, 2, 1, 0.03), (2, 4, 3, 0.5)]
)
def test_zoh_matches_matrix_exponential_and_integral(seed: int, n: int, m: int, dt: float) -> None:
    sys = _random_system(seed, n, m, 2)
    disc = sys.discretize(dt)
    bd_integral, _ = quad_vec(lambda tau: expm(sys.A * tau) @ sys.B, 0.0, dt, epsabs=1e-14)
    np.testing.assert_allclose(disc.Ad, expm(sys.A * dt), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(disc.Bd, bd_integral, rtol=1e-10, atol=1e-13)
    assert disc.dt == dt
    np.testing.assert_array_equal(disc.C, sys.C)
    np.testing.assert_array_equal(disc.D, sys.D)


def test_zoh_of_double_integrator_is_the_kinematic_closed_form() -> None:
    dt = 0.2
    Ad, Bd = zero_order_hold([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], dt)
    np.testing.assert_allclose(Ad, [[1.0, dt], [0.0, 1.0]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(Bd, [[dt**2 / 2], [dt]], rtol=1e-14)


def test_zoh_matches_python_control_c2d() -> None:
    sys = _random_system(3, 3, 2, 2)
    ours = sys.discretize(0.05)
    theirs = control.c2d(sys.to_control(), 0.05, method="zoh")
    np.testing.assert_allclose(ours.Ad, theirs.A, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(ours.Bd, theirs.B, rtol=1e-10, atol=1e-12)


def test_to_control_keeps_matrices_and_poles() -> None:
    sys = _random_system(4, 3, 1, 1)
    ss = sys.to_control()
    np.testing.assert_array_equal(ss.A, sys.A)
    np.testing.assert_allclose(np.sort_complex(ss.poles()), np.sort_complex(sys.poles()))
    assert (sys.n_states, sys.n_inputs, sys.n_outputs) == (3, 1, 1)


def test_simulate_double_integrator_under_constant_input() -> None:
    dt, u, N = 0.1, 2.0, 50
    sys = LinearSystem([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.5]])
    x, y = sys.discretize(dt).simulate(np.full(N, u), x0=[0.3, -0.1])
    t = dt * np.arange(N + 1)
    np.testing.assert_allclose(x[:, 0], 0.3 - 0.1 * t + u * t**2 / 2, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(x[:, 1], -0.1 + u * t, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(y, x[:-1, :1] + 0.5 * u, rtol=1e-12)
    assert x.shape == (N + 1, 2)
    assert y.shape == (N, 1)


def test_simulate_matches_python_control_forced_response() -> None:
    disc = _random_system(5, 3, 2, 2).discretize(0.02)
    u = np.random.default_rng(6).normal(size=(40, 2))
    x0 = np.array([0.1, -0.2, 0.3])
    x, y = disc.simulate(u, x0)
    resp = control.forced_response(disc.to_control(), U=u.T, X0=x0)
    np.testing.assert_allclose(y, resp.outputs.T, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(x[:-1], resp.states.T, rtol=1e-10, atol=1e-12)


def test_simulate_defaults_to_zero_initial_state() -> None:
    disc = _random_system(7, 2, 1, 1).discretize(0.1)
    x, y = disc.simulate(np.zeros(5))
    np.testing.assert_array_equal(x, np.zeros((6, 2)))
    np.testing.assert_array_equal(y, np.zeros((5, 1)))


def test_matrices_are_read_only() -> None:
    sys = _random_system(8, 2, 1, 1)
    with pytest.raises(ValueError, match="read-only"):
        sys.A[0, 0] = 1.0


def test_non_square_A_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"A must be square \(n, n\) with n >= 1, got shape"):
        LinearSystem(np.zeros((2, 3)), np.zeros((2, 1)), np.zeros((1, 2)), np.zeros((1, 1)))


def test_B_with_wrong_rows_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"B must have shape \(2, N\), got shape \(3, 1\)"):
        LinearSystem(np.eye(2), np.zeros((3, 1)), np.zeros((1, 2)), np.zeros((1, 1)))


def test_D_with_wrong_shape_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"D must have shape \(1, 1\), got shape \(1, 2\)"):
        LinearSystem(np.eye(2), np.zeros((2, 1)), np.zeros((1, 2)), np.zeros((1, 2)))


def test_nan_in_A_is_rejected() -> None:
    A = np.eye(2)
    A[1, 0] = np.nan
    with pytest.raises(ParameterError, match=r"A must be finite everywhere, got non-finite"):
        LinearSystem(A, np.zeros((2, 1)), np.zeros((1, 2)), np.zeros((1, 1)))


@pytest.mark.parametrize("dt", [0.0, -0.01])
def test_non_positive_dt_is_rejected(dt: float) -> None:
    with pytest.raises(ParameterError, match=f"dt must be > 0 s, got {dt} s"):
        _random_system(9, 2, 1, 1).discretize(dt)


def test_input_of_wrong_shape_is_rejected() -> None:
    disc = DiscreteLinearSystem(np.eye(2), np.zeros((2, 2)), np.eye(2), np.zeros((2, 2)), 0.1)
    with pytest.raises(ParameterError, match=r"u must have shape \(N, 2\), got shape \(5,\)"):
        disc.simulate(np.zeros(5))


def test_initial_state_of_wrong_shape_is_rejected() -> None:
    disc = _random_system(10, 2, 1, 1).discretize(0.1)
    with pytest.raises(ParameterError, match=r"x0 must have shape \(2\), got shape \(3,\)"):
        disc.simulate(np.zeros(4), x0=np.zeros(3))
