"""Preview control on the cart-table model (Kajita et al. 2003): gains and tracking."""

from __future__ import annotations

import control
import numpy as np
import pytest

from helpers.allocations import traced_growth_and_peak
from zmpkit.errors import ParameterError
from zmpkit.walking import (
    PreviewController,
    PreviewParameters,
    WalkCommand,
    cart_table_matrices,
    compute_preview_gains,
    linear_zmp_reference,
    plan_footsteps,
)

PARAMETERS = PreviewParameters()  # T = 10 ms, z_c = 0.26 m, horizon 1.6 s, Q_e = 1, R = 1e-6
GAINS = compute_preview_gains(PARAMETERS)

# Tracking on the cart-table model, paper B's walk: 0.2 m/s, 0.5 s steps, 10 s (20 steps),
# default gait. Measured: RMS 1.36 mm (x), 1.41 mm (y); max 6.57 mm (x), 6.57 mm (y).
TRACKING_RMS_TOLERANCE_M = 1.6e-3
TRACKING_MAX_TOLERANCE_M = 7.5e-3
# Rest at the end (1.5 s after the last transfer). Measured: |c - c_end| 1.7e-6 m,
# |c_dot| 1.0e-5 m/s, |c_ddot| 6.4e-5 m/s^2.
FINAL_POSITION_TOLERANCE_M = 1e-5
FINAL_VELOCITY_TOLERANCE_MPS = 5e-5
FINAL_ACCELERATION_TOLERANCE_MPS2 = 5e-4
# run() (blocked scan) vs a step() loop: round-off only; measured 2.7e-15 m, 5e-13 m/s^3.
RUN_VS_STEP_TOLERANCE_M = 1e-12
RUN_VS_STEP_JERK_TOLERANCE_MPS3 = 1e-9


@pytest.fixture(scope="module")
def walk():
    plan = plan_footsteps(WalkCommand(0.2, 0.0, 0.0), duration_s=10.0)
    reference = linear_zmp_reference(plan, PARAMETERS.sampling_period_s)
    trajectory = PreviewController(GAINS).run(reference.zmp_x_in_world, reference.zmp_y_in_world)
    return plan, reference, trajectory


def test_cart_table_matrices_integrate_a_constant_jerk_exactly() -> None:
    T, jerk = 0.01, 3.0
    A, B, C = cart_table_matrices(T, 0.26, 9.81)
    x0 = np.array([0.1, 0.2, 0.3])
    closed_form = [
        0.1 + 0.2 * T + 0.3 * T**2 / 2 + jerk * T**3 / 6,
        0.2 + 0.3 * T + jerk * T**2 / 2,
        0.3 + jerk * T,
    ]
    np.testing.assert_allclose(A @ x0 + B * jerk, closed_form, rtol=1e-15)
    assert C @ x0 == pytest.approx(0.1 - 0.26 / 9.81 * 0.3)


def test_riccati_solution_satisfies_the_dare() -> None:
    P, A, b = GAINS.riccati_solution, GAINS.augmented_a, GAINS.augmented_b[:, None]
    R = np.array([[PARAMETERS.jerk_weight]])
    residual = (
        A.T @ P @ A - P - A.T @ P @ b @ np.linalg.solve(R + b.T @ P @ b, b.T @ P @ A)
    ) + GAINS.augmented_q
    assert np.abs(residual).max() <= 1e-11 * np.abs(P).max()
    np.testing.assert_allclose(P, P.T, rtol=1e-12)
    assert np.all(np.linalg.eigvalsh(P) > -1e-9 * np.abs(P).max())


def test_integral_and_state_gains_equal_python_control_dlqr() -> None:
    # Independent reference: the LQR gain of the augmented system is [G_i, G_x].
    K, _, poles = control.dlqr(
        GAINS.augmented_a,
        GAINS.augmented_b[:, None],
        GAINS.augmented_q,
        np.array([[PARAMETERS.jerk_weight]]),
    )
    np.testing.assert_allclose(K[0], [GAINS.integral_gain, *GAINS.state_gain], rtol=1e-8)
    assert np.all(np.abs(poles) < 1.0)


def test_preview_gains_span_the_horizon_and_decay() -> None:
    gp = GAINS.preview_gains
    assert gp.size == PARAMETERS.preview_steps == 160
    assert gp[0] == pytest.approx(-GAINS.integral_gain)
    assert abs(gp[-1]) < 1e-3 * np.abs(gp).max()
    # The truncated tail is what keeps the law from being exactly translation-invariant.
    assert abs(GAINS.truncation_bias) < 2e-4 * abs(GAINS.state_gain[0])


def test_tracks_the_walking_reference_within_the_stated_tolerance(walk) -> None:
    _, _, trajectory = walk
    error = trajectory.zmp_error
    assert np.all(np.sqrt(np.mean(error**2, axis=0)) < TRACKING_RMS_TOLERANCE_M)
    assert np.all(np.abs(error).max(axis=0) < TRACKING_MAX_TOLERANCE_M)


def test_com_comes_to_rest_above_the_final_mid_feet_point(walk) -> None:
    plan, _, trajectory = walk
    left, right = plan.final_feet()
    centre = [(left.x + right.x) / 2, (left.y + right.y) / 2]
    assert centre == pytest.approx([1.85, 0.0])  # 0.1 m x (20 - 1.5) steps
    np.testing.assert_allclose(
        trajectory.com_position_in_world[-1], centre, atol=FINAL_POSITION_TOLERANCE_M
    )
    assert np.abs(trajectory.com_velocity_in_world[-1]).max() < FINAL_VELOCITY_TOLERANCE_MPS
    assert np.abs(trajectory.com_acceleration_in_world[-1]).max() < (
        FINAL_ACCELERATION_TOLERANCE_MPS2
    )


def test_returned_zmp_is_the_cart_table_output_of_the_returned_com(walk) -> None:
    _, _, tr = walk
    A, B, _ = cart_table_matrices(0.01, 0.26, 9.81)
    state = np.stack(
        [tr.com_position_in_world, tr.com_velocity_in_world, tr.com_acceleration_in_world]
    )  # (3, N, 2)
    propagated = (
        np.einsum("ij,jnk->ink", A, state[:, :-1]) + B[:, None, None] * (tr.com_jerk_in_world[:-1])
    )
    np.testing.assert_allclose(propagated, state[:, 1:], rtol=0, atol=1e-12)
    zmp = tr.com_position_in_world - 0.26 / 9.81 * tr.com_acceleration_in_world
    np.testing.assert_allclose(tr.zmp_in_world, zmp, rtol=0, atol=1e-15)
    # Positions alone: central second difference = acceleration + T (u_k - u_{k-1}) / 6.
    c = tr.com_position_in_world
    second = (c[2:] - 2 * c[1:-1] + c[:-2]) / 0.01**2
    jump = np.diff(tr.com_jerk_in_world, axis=0)[:-1]
    expected = tr.com_acceleration_in_world[1:-1] + 0.01 * jump / 6
    np.testing.assert_allclose(second, expected, atol=1e-8)


def test_run_equals_a_loop_of_steps(walk) -> None:
    _, reference, trajectory = walk
    controller = PreviewController(GAINS, initial_com_in_world=(0.0, 0.0))
    n_l, n = PARAMETERS.preview_steps, reference.time_s.size
    pad_x = np.concatenate([reference.zmp_x_in_world, np.full(n_l, reference.zmp_x_in_world[-1])])
    pad_y = np.concatenate([reference.zmp_y_in_world, np.full(n_l, reference.zmp_y_in_world[-1])])
    positions, jerks = np.empty((n, 2)), np.empty((n, 2))
    for k in range(n):
        positions[k] = controller.state_in_world[:, 0]
        controller.step(pad_x[k : k + n_l + 1], pad_y[k : k + n_l + 1])
        jerks[k] = controller.last_jerk_in_world
    np.testing.assert_allclose(
        positions, trajectory.com_position_in_world, rtol=0, atol=RUN_VS_STEP_TOLERANCE_M
    )
    np.testing.assert_allclose(
        jerks, trajectory.com_jerk_in_world, rtol=0, atol=RUN_VS_STEP_JERK_TOLERANCE_MPS3
    )


def test_constant_reference_far_from_the_origin_is_held() -> None:
    trajectory = PreviewController(GAINS).run(np.full(400, 5.0), np.full(400, -3.0))
    # Only the truncation bias acts: jerk -d * bias, removed by the integral term.
    assert np.abs(trajectory.com_position_in_world - [5.0, -3.0]).max() < 5e-4
    assert np.abs(trajectory.zmp_error).max() < 5e-3


def test_step_allocates_no_arrays() -> None:
    controller = PreviewController(GAINS, initial_com_in_world=(0.1, 0.0))
    window = np.linspace(0.1, 0.2, controller.window_length)
    for _ in range(5):
        controller.step(window, window)

    growth, peak = traced_growth_and_peak(lambda _: controller.step(window, window), 500)
    assert growth < 256  # no growth
    assert peak < 1024  # never as much as one (N_L + 1)-array (1288 bytes)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda c: c.run([0.0, np.nan], [0.0, 0.0]), r"zmp_ref_x must be finite everywhere"),
        (lambda c: c.run([0.0, 1.0], [0.0]), r"must be non-empty and of equal length, got 2 and 1"),
        (lambda c: c.run(np.zeros((3, 2)), np.zeros(3)), r"zmp_ref_x must have shape \(N\)"),
        (lambda c: c.step(np.zeros(5), np.zeros(5)), r"windows must have length N_L \+ 1 = 161"),
    ],
)
def test_bad_references_name_the_argument(call, message) -> None:
    with pytest.raises(ParameterError, match=message):
        call(PreviewController(GAINS))


def test_bad_parameters_name_the_field() -> None:
    with pytest.raises(ParameterError, match=r"horizon_s must span at least one period"):
        PreviewParameters(horizon_s=0.001)
    with pytest.raises(ParameterError, match=r"PreviewParameters.com_height_m must be > 0 m"):
        PreviewParameters(com_height_m=0.0)
