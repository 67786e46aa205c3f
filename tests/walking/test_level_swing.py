"""The swing soles' pitch that cancels the trunk's (:mod:`zmpkit.walking.level_swing`)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.walking.level_swing import IN_AIR_M, LevelSwing


def _pitched(pitch_rad: float, yaw_rad: float = 0.0) -> np.ndarray:
    """The quaternion (w, x, y, z) of ``R_z(ψ) R_y(θ)`` (ZYX Euler, roll 0)."""
    cy, sy = math.cos(yaw_rad / 2), math.sin(yaw_rad / 2)
    cp, sp = math.cos(pitch_rad / 2), math.sin(pitch_rad / 2)
    return np.array([cy * cp, -sy * sp, cy * sp, sy * cp])


@given(
    start=st.floats(-0.3, 0.3), pitch=st.floats(-0.6, 0.6), yaw=st.floats(-3.0, 3.0),
    height=st.floats(2 * IN_AIR_M, 0.1),
)  # fmt: skip
def test_a_foot_in_the_air_is_pitched_back_by_the_trunks_pitch_change(
    start: float, pitch: float, yaw: float, height: float
) -> None:
    level = LevelSwing(enabled=True)
    level.update(_pitched(start, yaw))
    level.update(_pitched(pitch, yaw))
    assert level.trunk_pitch_change_rad == pytest.approx(pitch - start, abs=1e-9)
    assert level.foot_pitch_rad(height) == pytest.approx(start - pitch, abs=1e-9)


@pytest.mark.parametrize("height", [0.0, IN_AIR_M, -0.01])
def test_a_foot_on_the_ground_stays_parallel_to_it(height: float) -> None:
    level = LevelSwing(enabled=True)
    level.update(_pitched(0.0))
    level.update(_pitched(0.2))
    assert level.foot_pitch_rad(height) == 0.0


def test_disabled_every_sole_stays_parallel_to_the_ground() -> None:
    level = LevelSwing(enabled=False)
    level.update(_pitched(0.0))
    level.update(_pitched(0.2))
    assert level.foot_pitch_rad(0.05) == 0.0
