"""Trunk tilt of many IMU quaternions: the scalar rule, row by row, and closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from zmpkit.sensors.imu import quaternion_pitch_roll, tilt_from_quaternions


def test_series_equals_the_scalar_rule_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    quats = rng.normal(size=(500, 4))
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    pitch_roll = np.array([quaternion_pitch_roll(q) for q in quats])
    assert np.array_equal(tilt_from_quaternions(quats, "sagittal"), pitch_roll[:, 0])
    assert np.array_equal(tilt_from_quaternions(quats, "frontal"), pitch_roll[:, 1])


@pytest.mark.parametrize(("axis", "plane"), [((0, 1, 0), "sagittal"), ((1, 0, 0), "frontal")])
def test_rotation_about_one_axis_is_its_angle(axis: tuple[int, int, int], plane: str) -> None:
    angles = np.linspace(-1.2, 1.2, 9)  # [rad], inside (-pi/2, pi/2)
    quats = np.array([[math.cos(a / 2), *(math.sin(a / 2) * np.array(axis))] for a in angles])
    np.testing.assert_allclose(tilt_from_quaternions(quats, plane), angles, atol=1e-12)


def test_no_quaternions_give_no_angles() -> None:
    assert tilt_from_quaternions(np.empty((0, 4)), "sagittal").shape == (0,)
