"""When a moved swing lands, and where its foot is (:mod:`zmpkit.walking.measured_footholds`)."""

from __future__ import annotations

import numpy as np
import pytest

from zmpkit.walking.measured_footholds import MeasuredFootholds

LIFT, TOUCHDOWN = 100, 140.0  # a 0.4 s swing at 100 Hz [frames]


class _Estimator:
    """What the footholds read of a state estimator: the feet's loads and measured soles."""

    def __init__(self, left_load_n: float) -> None:
        self.force_z_n = np.array([left_load_n, 40.0])
        self.threshold_n = 5.0
        self.soles = np.array([[0.61, 0.07, 0.012], [0.55, -0.05, 0.0]])

    def sole_in_world(self, foot: int, axis: int) -> float:
        return float(self.soles[foot, axis])


def _footholds(left_load_n: float, fraction: float = 0.5) -> MeasuredFootholds:
    return MeasuredFootholds(_Estimator(left_load_n), fraction)  # type: ignore[arg-type]


def _swung(left_load_n: float, fraction: float = 0.5) -> MeasuredFootholds:
    """Footholds whose left foot was in the air (unloaded) just after lift-off."""
    estimator = _Estimator(0.0)
    footholds = MeasuredFootholds(estimator, fraction)  # type: ignore[arg-type]
    footholds.lift()
    assert not footholds.landed(0, LIFT + 1, LIFT, TOUCHDOWN)
    estimator.force_z_n[0] = left_load_n
    return footholds


@pytest.mark.parametrize("frame", [101, 110, 119])
def test_a_contact_early_in_the_swing_is_not_its_touchdown(frame: int) -> None:
    """Lift-off's last load and a scuff before half the swing do not end it."""
    assert not _footholds(30.0).landed(0, frame, LIFT, TOUCHDOWN)
    assert not _swung(30.0).landed(0, frame, LIFT, TOUCHDOWN)


@pytest.mark.parametrize("frame", [120, 130, 139])
def test_a_contact_after_the_share_of_the_swing_is_its_touchdown(frame: int) -> None:
    assert _swung(30.0).landed(0, frame, LIFT, TOUCHDOWN)
    assert not _swung(4.9).landed(0, frame, LIFT, TOUCHDOWN)  # below the threshold


@pytest.mark.parametrize("frame", [120, 130, 139])
def test_a_foot_that_never_left_the_ground_is_not_landing(frame: int) -> None:
    """Loaded since lift-off (the robot stands on it): down only at its touchdown."""
    footholds = _footholds(30.0)
    footholds.lift()
    for earlier in range(LIFT + 1, frame + 1):
        assert not footholds.landed(0, earlier, LIFT, TOUCHDOWN)
    assert footholds.landed(0, 140, LIFT, TOUCHDOWN)


def test_a_lift_off_forgets_the_last_swing_in_the_air() -> None:
    footholds = _swung(30.0)
    footholds.lift()
    assert not footholds.landed(0, 130, LIFT, TOUCHDOWN)


def test_the_swing_is_down_at_its_touchdown_loaded_or_not() -> None:
    assert _footholds(0.0).landed(0, 140, LIFT, TOUCHDOWN)
    assert not _footholds(0.0).landed(0, 139, LIFT, TOUCHDOWN)


def test_a_share_of_one_lands_only_at_the_touchdown() -> None:
    assert not _swung(30.0, 1.0).landed(0, 139, LIFT, TOUCHDOWN)


def test_the_foot_is_where_the_estimate_measures_it() -> None:
    footholds = _footholds(30.0)
    assert [footholds.at(0, axis) for axis in range(3)] == [0.61, 0.07, 0.012]
