"""Tests of zmpkit.models.pendulum against closed forms and numerical integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from zmpkit.errors import ParameterError
from zmpkit.models.pendulum import (
    STANDARD_GRAVITY_MPS2,
    CartTable,
    InvertedPendulum,
    Lipm,
    Lipm3D,
)

TEO_MASS_KG = 62.6  # paper A §4.1
TEO_COM_HEIGHT_M = 0.893  # paper A §4.1


@pytest.mark.parametrize(
    ("z_c", "x0", "v0", "zmp"),
    [(0.893, 0.02, 0.0, 0.05), (0.26, -0.01, 0.15, 0.0), (1.2, 0.0, -0.3, -0.04)],
)
def test_lipm_closed_form_matches_numerical_integration(
    z_c: float, x0: float, v0: float, zmp: float
) -> None:
    lipm = Lipm(z_c)
    t = np.linspace(0.0, 1.5, 61)
    sol = solve_ivp(
        lambda _t, s: [s[1], lipm.omega**2 * (s[0] - zmp)],
        (0.0, 1.5),
        [x0, v0],
        method="DOP853",
        t_eval=t,
        rtol=1e-12,
        atol=1e-14,
    )
    traj = lipm.closed_form(t, x0, v0, zmp)
    np.testing.assert_allclose(traj.com_position, sol.y[0], rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(traj.com_velocity, sol.y[1], rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(traj.com_acceleration, lipm.omega**2 * (sol.y[0] - zmp), rtol=1e-8)


def test_lipm_omega_and_state_space() -> None:
    lipm = Lipm(TEO_COM_HEIGHT_M)
    assert lipm.omega == pytest.approx(math.sqrt(9.81 / 0.893), rel=1e-15)
    assert lipm.g == STANDARD_GRAVITY_MPS2
    poles = np.sort(lipm.state_space().poles().real)
    np.testing.assert_allclose(poles, [-lipm.omega, lipm.omega], rtol=1e-12)


def test_lipm_state_space_zoh_reproduces_closed_form() -> None:
    lipm, dt, zmp = Lipm(0.8), 0.01, 0.03
    x, y = lipm.state_space().discretize(dt).simulate(np.full(100, zmp), x0=[0.01, 0.05])
    traj = lipm.closed_form(dt * np.arange(101), 0.01, 0.05, zmp)
    np.testing.assert_allclose(x[:, 0], traj.com_position, rtol=1e-10, atol=1e-13)
    np.testing.assert_allclose(x[:, 1], traj.com_velocity, rtol=1e-10, atol=1e-13)
    np.testing.assert_allclose(y[:, 0], traj.com_position[:-1], rtol=1e-10, atol=1e-13)


def test_lipm_orbital_energy_is_conserved() -> None:
    lipm = Lipm(0.7)
    traj = lipm.closed_form(np.linspace(0.0, 2.0, 50), 0.05, -0.2, 0.01)
    energy = lipm.orbital_energy(traj.com_position, traj.com_velocity, 0.01)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-9, atol=1e-14)
    assert lipm.orbital_energy(0.05, -0.2, 0.01) == pytest.approx(
        0.5 * 0.04 - 0.5 * 9.81 / 0.7 * 0.0016
    )


def test_lipm3d_is_two_independent_lipms() -> None:
    lipm3d, t = Lipm3D(0.6, g=9.8), np.linspace(0.0, 1.0, 21)
    traj = lipm3d.closed_form(t, [0.01, -0.02], [0.1, 0.05], [0.03, -0.04])
    for axis, (x0, v0, p) in enumerate([(0.01, 0.1, 0.03), (-0.02, 0.05, -0.04)]):
        one = Lipm(0.6, g=9.8).closed_form(t, x0, v0, p)
        np.testing.assert_allclose(traj.com_position[:, axis], one.com_position, rtol=1e-14)
        np.testing.assert_allclose(traj.com_velocity[:, axis], one.com_velocity, rtol=1e-14)
    energy = lipm3d.orbital_energy(traj.com_position, traj.com_velocity, [0.03, -0.04])
    np.testing.assert_allclose(energy, np.broadcast_to(energy[0], energy.shape), rtol=1e-9)


def test_lipm3d_state_space_zoh_reproduces_closed_form() -> None:
    lipm3d, dt = Lipm3D(0.9), 0.02
    u = np.tile([0.02, -0.01], (30, 1))
    x, _ = lipm3d.state_space().discretize(dt).simulate(u, x0=[0.0, 0.01, 0.1, 0.0])
    traj = lipm3d.closed_form(dt * np.arange(31), [0.0, 0.01], [0.1, 0.0], [0.02, -0.01])
    np.testing.assert_allclose(x[:, :2], traj.com_position, rtol=1e-10, atol=1e-13)
    np.testing.assert_allclose(x[:, 2:], traj.com_velocity, rtol=1e-10, atol=1e-13)


def test_cart_table_output_is_zmp_of_the_states() -> None:
    cart, dt = CartTable(0.8), 0.005
    jerk = np.random.default_rng(0).normal(size=200)
    x, y = cart.state_space().discretize(dt).simulate(jerk, x0=[0.0, 0.1, -0.2])
    expected = x[:-1, 0] - 0.8 / 9.81 * x[:-1, 2]
    np.testing.assert_allclose(y[:, 0], expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(cart.zmp_from_com(x[:-1, 0], x[:-1, 2]), expected, rtol=1e-15)


def test_cart_table_zoh_under_constant_jerk_is_cubic() -> None:
    dt, j = 0.3, 1.5
    x, _ = CartTable(0.8).state_space().discretize(dt).simulate([j], x0=[0.1, 0.2, 0.3])
    expected = [0.1 + 0.2 * dt + 0.3 * dt**2 / 2 + j * dt**3 / 6, 0.2 + 0.3 * dt + j * dt**2 / 2]
    np.testing.assert_allclose(x[1, :2], expected, rtol=1e-13)
    assert x[1, 2] == pytest.approx(0.3 + j * dt, rel=1e-13)


def test_cart_table_recovers_the_lipm_zmp() -> None:
    traj = Lipm(0.75).closed_form(np.linspace(0.0, 1.0, 30), 0.02, 0.1, 0.04)
    zmp = CartTable(0.75).zmp_from_com(traj.com_position, traj.com_acceleration)
    np.testing.assert_allclose(zmp, 0.04, rtol=1e-12)


def _small_angle_gap(theta0: float) -> float:
    """Largest |l θ(t) − x_LIPM(t)| over 0.6 s, relative to the largest |x_LIPM|."""
    pendulum, t = InvertedPendulum(TEO_MASS_KG, TEO_COM_HEIGHT_M), np.linspace(0.0, 0.6, 61)
    response = pendulum.simulate(t, theta0, 0.0)
    lipm = Lipm(TEO_COM_HEIGHT_M).closed_form(t, TEO_COM_HEIGHT_M * theta0, 0.0, 0.0)
    gap = np.max(np.abs(pendulum.expected_zmp_linearised(response.theta) - lipm.com_position))
    return float(gap / np.max(np.abs(lipm.com_position)))


def test_nonlinear_pendulum_agrees_with_lipm_at_small_angles() -> None:
    # the neglected term is sin θ − θ ≈ −θ³/6: the relative gap scales with θ².
    gap_small, gap_half = _small_angle_gap(2e-3), _small_angle_gap(1e-3)
    assert gap_small < 1e-5
    assert gap_small / gap_half == pytest.approx(4.0, rel=0.02)


def test_nonlinear_pendulum_conserves_energy_without_torque() -> None:
    pendulum = InvertedPendulum(TEO_MASS_KG, TEO_COM_HEIGHT_M)
    response = pendulum.simulate(np.linspace(0.0, 2.0, 201), 0.1, -0.05)
    energy = pendulum.energy(response.theta, response.theta_dot)
    assert np.ptp(response.theta) > 1.0  # it falls far past the small-angle range
    np.testing.assert_allclose(energy, energy[0], rtol=1e-9)
    np.testing.assert_array_equal(response.torque, 0.0)


def test_static_torque_holds_the_pendulum() -> None:
    pendulum, theta0 = InvertedPendulum(TEO_MASS_KG, TEO_COM_HEIGHT_M), 0.05
    holding = TEO_MASS_KG * 9.81 * TEO_COM_HEIGHT_M * math.sin(theta0)
    response = pendulum.simulate(np.linspace(0.0, 1.0, 11), theta0, 0.0, torque=holding)
    np.testing.assert_allclose(response.theta, theta0, rtol=1e-9)


def test_torque_law_is_called_and_recorded() -> None:
    pendulum = InvertedPendulum(10.0, 1.0)
    gains = (400.0, 60.0)  # PD on the angle, strong enough to stabilise: k > m g l

    def law(_t: float, theta: float, theta_dot: float) -> float:
        return gains[0] * theta + gains[1] * theta_dot

    response = pendulum.simulate(np.linspace(0.0, 5.0, 101), 0.1, 0.0, torque=law)
    assert abs(response.theta[-1]) < 1e-3
    np.testing.assert_allclose(
        response.torque, gains[0] * response.theta + gains[1] * response.theta_dot, rtol=1e-12
    )


def test_expected_zmp_and_static_angle_round_trip() -> None:
    pendulum = InvertedPendulum(TEO_MASS_KG, TEO_COM_HEIGHT_M)
    zmp = np.array([-0.1, 0.0, 0.05, 0.893])
    theta = pendulum.static_angle_for_zmp(zmp)
    np.testing.assert_allclose(pendulum.expected_zmp(theta), zmp, rtol=1e-14, atol=1e-16)
    assert pendulum.static_angle_for_zmp(0.893) == pytest.approx(math.pi / 2)
    assert pendulum.expected_zmp_linearised(0.1) == pytest.approx(0.0893)
    assert pendulum.expected_zmp(0.1) == pytest.approx(0.893 * math.sin(0.1))


def test_zmp_out_of_reach_is_rejected() -> None:
    pendulum = InvertedPendulum(TEO_MASS_KG, TEO_COM_HEIGHT_M)
    with pytest.raises(ParameterError, match=r"ZMP \|x\| = 1.2 m is out of reach .* l = 0.893 m"):
        pendulum.static_angle_for_zmp(-1.2)


def test_negative_mass_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"mass must be > 0 kg, got -1.0 kg"):
        InvertedPendulum(-1.0, 0.9)


def test_zero_length_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"length must be > 0 m, got 0.0 m"):
        InvertedPendulum(60.0, 0.0)


@pytest.mark.parametrize("model", [Lipm, Lipm3D, CartTable])
def test_nan_com_height_is_rejected(model: type) -> None:
    with pytest.raises(ParameterError, match=r"com_height must be finite, got nan"):
        model(float("nan"))


def test_non_increasing_time_is_rejected() -> None:
    pendulum = InvertedPendulum(60.0, 0.9)
    with pytest.raises(ParameterError, match=r"t must be strictly increasing, but t\[2\] = 0.1"):
        pendulum.simulate([0.0, 0.1, 0.1], 0.0, 0.0)


def test_lipm3d_wrong_zmp_shape_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"zmp must have shape \(2\), got shape \(3,\)"):
        Lipm3D(0.8).closed_form([0.0, 0.1], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0, 0.0])
