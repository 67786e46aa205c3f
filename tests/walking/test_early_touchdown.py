"""The early touchdown hold against its closed form, and its invariants (hypothesis)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.walking.early_touchdown import EarlyTouchdown

PERIOD_S = 0.01
FLOOR_M = 0.002  # the plan's floor level (a sole site a little above the floor)


def _swing() -> np.ndarray:
    """One foot's planned height: 10 frames on the floor, a 40-frame swing, 30 on the floor."""
    lift = FLOOR_M + 0.02 * np.sin(np.linspace(0.0, np.pi, 41))[1:-1]
    return np.concatenate([np.full(10, FLOOR_M), [FLOOR_M], lift, [FLOOR_M], np.full(30, FLOOR_M)])


def _run(plan: np.ndarray, loaded: np.ndarray, release_s: float = 0.1) -> np.ndarray:
    commanded = plan.copy()
    hold = EarlyTouchdown([plan], [commanded], PERIOD_S, release_s)
    for frame in range(plan.size):  # the force read at frame - 1 acts on frame
        force = np.array([30.0 if frame > 0 and loaded[frame - 1] else 0.0])
        hold.update(frame, force, 5.0)
    return commanded


def test_an_early_touchdown_holds_the_sole_and_releases_it_over_t_r() -> None:
    plan = _swing()
    touch = 40  # in the descent: the plan's touchdown is frame 50
    loaded = np.zeros(plan.size, dtype=bool)
    loaded[touch:] = True
    commanded = _run(plan, loaded)
    held = plan[touch]  # the command the frame before the hold acts: that of frame 40
    np.testing.assert_array_equal(commanded[: touch + 1], plan[: touch + 1])
    np.testing.assert_array_equal(commanded[touch + 1 : 50], held)
    # from the planned touchdown (frame 50), back to the plan over 0.1 s = 10 frames
    expected = plan[50:60] + (held - FLOOR_M) * (1.0 - np.arange(10) / 10.0)
    np.testing.assert_allclose(commanded[50:60], expected, atol=1e-15)
    np.testing.assert_array_equal(commanded[60:], plan[60:])


def test_no_load_in_the_air_leaves_the_plan_alone_and_a_bounce_keeps_the_hold() -> None:
    plan = _swing()
    np.testing.assert_array_equal(_run(plan, np.zeros(plan.size, dtype=bool)), plan)
    rising = np.zeros(plan.size, dtype=bool)
    rising[10:20] = True  # a sole still loaded as it rises: not an early touchdown
    np.testing.assert_array_equal(_run(plan, rising), plan)
    bounce = np.zeros(plan.size, dtype=bool)
    bounce[42:44] = True  # touches, leaves the floor again
    commanded = _run(plan, bounce)
    np.testing.assert_array_equal(commanded[44:50], plan[42])


@given(
    touch=st.integers(min_value=0, max_value=89),
    length=st.integers(min_value=1, max_value=90),
    release_s=st.floats(min_value=0.01, max_value=0.5),
)
def test_the_command_never_goes_below_the_plan_and_returns_to_it(
    touch: int, length: int, release_s: float
) -> None:
    """Wherever it writes, the hold keeps the sole at or above its plan, and the command is
    the plan again once the release is over."""
    plan = _swing()
    loaded = np.zeros(plan.size, dtype=bool)
    loaded[touch : touch + length] = True
    commanded = _run(plan, loaded, release_s)
    assert np.all(commanded >= plan - 1e-15)
    end = 50 + int(np.ceil(release_s / PERIOD_S)) + 1
    if end < plan.size:
        np.testing.assert_array_equal(commanded[end:], plan[end:])


def test_bad_settings_are_refused() -> None:
    plan = _swing()
    with pytest.raises(ParameterError, match="period_s"):
        EarlyTouchdown([plan], [plan.copy()], 0.0)
    with pytest.raises(ParameterError, match="a planned and a commanded"):
        EarlyTouchdown([plan], [], PERIOD_S)
