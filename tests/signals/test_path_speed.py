"""The speed along a path with its sway averaged out: closed forms and invariances."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.signals.contact_phases import fitted_speed, path_speed

DT_S = 0.002
PERIOD_S = 1.0  # a gait cycle of two 0.5 s steps


def _swaying(path_xy: np.ndarray, heading: np.ndarray, t: np.ndarray, sway_m: float):
    """The path plus a sideways sway of the gait period (the torso over each stance foot)."""
    normal = np.column_stack([-np.sin(heading), np.cos(heading)])
    return path_xy + sway_m * np.sin(2.0 * np.pi * t / PERIOD_S)[:, None] * normal


def _circle(speed: float, turn: float, t: np.ndarray, sway_m: float) -> np.ndarray:
    heading = turn * t
    radius = speed / turn
    xy = np.column_stack([radius * np.sin(heading), radius * (1.0 - np.cos(heading))])
    return _swaying(xy, heading, t, sway_m)


def test_a_circle_is_walked_at_its_speed_where_the_fitted_x_speed_is_its_chord() -> None:
    t = np.arange(0.0, 8.0 + DT_S / 2, DT_S)
    speed, turn = 0.15, 0.2  # [m/s], [rad/s]: the turning walk
    xy = _circle(speed, turn, t, sway_m=0.02)
    window = t >= 2.0
    assert path_speed(t, xy, window, PERIOD_S) == pytest.approx(speed, rel=1e-3)
    # x(t) = R sin(ωt): its fitted slope is well below v once the walk has turned 0.4-1.6 rad
    assert fitted_speed(t, xy[:, 0], window) < 0.8 * speed


def test_a_straight_walk_has_its_fitted_speed() -> None:
    t = np.arange(0.0, 6.0 + DT_S / 2, DT_S)
    xy = _swaying(np.column_stack([0.2 * t, np.zeros_like(t)]), np.zeros_like(t), t, 0.03)
    window = (t >= 1.0) & (t <= 5.5)
    assert path_speed(t, xy, window, PERIOD_S) == pytest.approx(0.2, rel=1e-6)
    assert fitted_speed(t, xy[:, 0], window) == pytest.approx(0.2, rel=1e-6)


@settings(max_examples=40, deadline=None)
@given(
    speed=st.floats(0.05, 0.4),
    turn=st.floats(-0.5, 0.5).filter(lambda w: abs(w) > 1e-3),
    angle=st.floats(-math.pi, math.pi),
    shift=st.tuples(st.floats(-5.0, 5.0), st.floats(-5.0, 5.0)),
    sway=st.floats(0.0, 0.04),
)
def test_invariant_to_where_and_which_way_the_walk_goes(speed, turn, angle, shift, sway) -> None:
    t = np.arange(0.0, 5.0 + DT_S / 2, DT_S)
    xy = _circle(speed, turn, t, sway)
    c, s = math.cos(angle), math.sin(angle)
    moved = xy @ np.array([[c, s], [-s, c]]) + np.asarray(shift)
    window = t >= 1.0
    here = path_speed(t, xy, window, PERIOD_S)
    assert path_speed(t, moved, window, PERIOD_S) == pytest.approx(here, rel=1e-9, abs=1e-12)
    # the closed form: v, up to the sway's residue a·ω²T/(2π) (the docstring's bound)
    residue = sway * turn**2 * PERIOD_S / (2.0 * math.pi)
    assert abs(here - speed) <= residue + 1e-3 * speed
    assert path_speed(t, _circle(speed, turn, t, 0.0), window, PERIOD_S) == pytest.approx(
        speed, rel=1e-3
    )


@pytest.mark.parametrize(
    ("period", "window_end", "message"),
    [
        (0.0, 5.0, r"period_s must be > 0 s, got 0\.0"),
        (1.0, 1.5, r"at least two periods \(2 s\) to measure a path speed; got 1\.5 s"),
    ],
)
def test_bad_windows_are_named(period: float, window_end: float, message: str) -> None:
    t = np.arange(0.0, 5.0 + DT_S / 2, DT_S)
    xy = np.column_stack([0.1 * t, 0.0 * t])
    with pytest.raises(ParameterError, match=message):
        path_speed(t, xy, t <= window_end, period)
