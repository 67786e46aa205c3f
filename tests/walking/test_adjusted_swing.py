"""A re-planned swing: the plan's own swing when nothing changes, smooth when the goal moves."""

from __future__ import annotations

import numpy as np
import pytest

from zmpkit.walking import generate_pattern
from zmpkit.walking.adjusted_swing import AdjustedSwing
from zmpkit.walking.swing import swing_edges


def _swing(frames: range, swing: AdjustedSwing) -> np.ndarray:
    out = []
    for k in frames:
        swing.advance(float(k))
        out.append((swing.x_m, swing.y_m, swing.z_m))
    return np.array(out)


def test_an_unchanged_swing_is_the_planned_one() -> None:
    pattern = generate_pattern()
    left = pattern.feet.left
    lift, land = next(iter(swing_edges(left.in_contact).items()))
    start, goal = left.position_in_world[lift - 1], left.position_in_world[land]
    swing = AdjustedSwing(pattern.config.step_height_m)
    swing.start(float(lift - 1), start[0], start[1], goal[0], goal[1], float(land))
    path = _swing(range(lift, land + 1), swing)
    np.testing.assert_allclose(path, left.position_in_world[lift : land + 1], atol=1e-12)


def test_a_moved_goal_is_reached_at_rest_without_a_jump() -> None:
    swing = AdjustedSwing(0.02)
    swing.start(0.0, 0.0, 0.0, 0.1, 0.0, 40.0)
    before = _swing(range(1, 16), swing)
    swing.retarget(15.0, 0.18, 0.05, 30.0)  # further, sideways and 10 frames earlier
    after = _swing(range(15, 31), swing)
    assert after[0] == pytest.approx(before[-1])  # the target of frame 15 is unchanged
    path = np.vstack([before, after[1:]])
    assert path[-1] == pytest.approx((0.18, 0.05, 0.0))
    steps = np.diff(path[:, :2], axis=0)
    assert np.max(np.abs(np.diff(steps, axis=0))) < 0.004  # no jump in velocity [m/frame]
    assert np.abs(steps[-1]).max() < 1e-3  # at rest when it lands
    assert np.all(path[:-1, 2] > 0.0)  # in the air until the new touchdown
