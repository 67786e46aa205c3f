"""The ZMP/IP observer: a stable gain, an idle observer keeps the plan, an offset is removed."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.cart_table import PreviewParameters, compute_preview_gains
from zmpkit.walking.zmp_observer import (
    ObservedPreviewControl,
    ZmpObserverParameters,
    observer_gain,
    observer_matrices,
)

T, ZC, G = 0.01, 0.25, 9.81


@given(
    com=st.floats(1e-3, 0.1),
    zmp=st.floats(1e-3, 0.1),
    jerk=st.floats(0.1, 100.0),
    drift=st.floats(1e-5, 1e-2),
)
@settings(max_examples=30, deadline=None)
def test_the_estimation_error_decays_for_any_noise_levels(com, zmp, jerk, drift) -> None:
    """Error of the filter's prior: e_{k+1} = A_z (I - L C) e_k, spectral radius < 1."""
    parameters = ZmpObserverParameters(com, zmp, jerk, drift)
    a, _, c = observer_matrices(T, ZC, G)
    gain = observer_gain(parameters, T, ZC, G)
    assert gain.shape == (4, 2)
    radius = max(abs(np.linalg.eigvals(a @ (np.eye(4) - gain @ c))))
    assert radius < 1.0


def test_an_idle_observer_plays_the_planned_com() -> None:
    """Measurements equal to the model's prediction: no correction, the preview plan itself."""
    pattern = generate_pattern(
        PatternConfig(
            command=WalkCommand(v_x=0.2),
            duration_s=3.0,
            gait=GaitParameters(step_duration_s=0.5),
            com_height_m=ZC,
        )
    )
    com = pattern.com
    initial = np.column_stack(
        [com.com_position_in_world[0], com.com_velocity_in_world[0],
         com.com_acceleration_in_world[0]]
    )  # fmt: skip
    control = ObservedPreviewControl(pattern.gains, pattern.zmp_reference_in_world, initial)
    c3 = np.array([1.0, 0.0, -ZC / pattern.gains.parameters.gravity_mps2])
    n = pattern.time_s.size
    planned = np.empty((n, 2))
    planned[0] = control.state[:, 0]
    for k in range(n - 1):
        measured_com = control.state[:, 0].copy()
        measured_zmp = control.state[:, :3] @ c3
        planned[k + 1] = control.update(k, measured_com, measured_zmp)
    np.testing.assert_allclose(planned, com.com_position_in_world, atol=1e-9)


def test_a_constant_zmp_offset_is_estimated_and_removed() -> None:
    """Closed form: standing with p_ref = 0 and a robot whose ZMP reads d higher than the cart
    table's, the steady state has d̂ = d, the CoM at -d and the measured ZMP at 0."""
    gains = compute_preview_gains(PreviewParameters(sampling_period_s=T, com_height_m=ZC))
    n = 6000  # 60 s: the offset's estimate settles in tens of seconds (σ_d 0.1 mm a period)
    reference = np.zeros((n, 2))
    offset = np.array([0.012, -0.008])  # [m]
    control = ObservedPreviewControl(gains, reference, np.zeros((2, 3)))
    g = gains.parameters.gravity_mps2
    a, b, _ = observer_matrices(T, ZC, g)
    robot = np.zeros((2, 3))  # the robot's true cart-table state, rows x, y
    c3 = np.array([1.0, 0.0, -ZC / g])
    for k in range(n - 1):
        measured_zmp = robot @ c3 + offset
        control.update(k, robot[:, 0].copy(), measured_zmp)
        for axis in (0, 1):  # the robot is the cart table, driven by the controller's jerk
            robot[axis] = a[:3, :3] @ robot[axis] + b[:3] * control.jerk_in_world[axis]
    np.testing.assert_allclose(control.offset_in_world, offset, atol=1e-5)
    np.testing.assert_allclose(robot[:, 0], -offset, atol=1e-5)
    np.testing.assert_allclose(robot @ c3 + offset, 0.0, atol=1e-5)


def test_noise_levels_must_be_positive() -> None:
    with pytest.raises(ValueError, match="zmp_noise_m"):
        ZmpObserverParameters(zmp_noise_m=0.0)


def test_a_zmp_spike_moves_the_estimate_no_more_than_the_clip() -> None:
    """Robust correction: a ZMP 1 m off acts as one max_zmp_innovation_m off."""
    gains = compute_preview_gains(PreviewParameters(sampling_period_s=T, com_height_m=ZC))
    reference = np.zeros((10, 2))
    parameters = ZmpObserverParameters()
    spiked = ObservedPreviewControl(gains, reference, np.zeros((2, 3)), parameters)
    clipped = ObservedPreviewControl(gains, reference, np.zeros((2, 3)), parameters)
    spiked.update(0, np.zeros(2), np.array([1.0, -1.0]))
    clip = parameters.max_zmp_innovation_m
    clipped.update(0, np.zeros(2), np.array([clip, -clip]))
    np.testing.assert_array_equal(spiked.state, clipped.state)
    assert 0.0 < spiked.offset_in_world[0] < clip
