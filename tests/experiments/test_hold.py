"""The hold monitor on synthetic F-T wrenches of a known ZMP: settled, creeping, tipping."""

from __future__ import annotations

import numpy as np
import pytest

from zmpkit.experiments.hold import (
    LIFT_LOAD_FRACTION,
    TIP_EDGE_FRACTION,
    HoldMonitor,
)
from zmpkit.io import feet_from_mapping
from zmpkit.robots.registry import get_robot
from zmpkit.robots.teo import teo_feet_mounts

RATE_HZ = 200.0
WEIGHT_N = 614.0  # 62.6 kg × g
FEET = teo_feet_mounts()
T_STEP_S = 0.5


def support_polygon(plane: str) -> tuple[float, float]:
    """TEO's double-support extent in ``plane`` [m] (its balance model's)."""
    return get_robot("teo").require_balance().support_polygon_m[plane]


def _wrench(point: np.ndarray, load_n: float, foot: str) -> np.ndarray:
    """Sensor-frame wrench of a vertical point load [N] at ``point`` (sensors not rotated)."""
    sensor = np.asarray(FEET[foot]["position"])
    force = np.array([0.0, 0.0, load_n])
    return np.concatenate([force, np.cross(point - sensor, force)])


def _feed(monitor: HoldMonitor, plane: str, zmp, duration_s: float, seed: int = 0) -> float:
    """Feed wrenches whose double-support ZMP is ``zmp(t)`` [m]; returns the last time [s]."""
    rng = np.random.default_rng(seed)
    y_r, y_l = FEET["right"]["position"][1], FEET["left"]["position"][1]
    for t in np.arange(0.0, duration_s, 1.0 / RATE_HZ):
        p = zmp(t - T_STEP_S) + rng.normal(0.0, 5e-5)
        x, y = (p, 0.0) if plane == "sagittal" else (0.0, p)
        right = WEIGHT_N * (y_l - y) / (y_l - y_r)  # each foot's load at its own centre line
        wrenches = [
            _wrench(np.array([x, y_foot, 0.0]), load, side)
            for side, y_foot, load in (("right", y_r, right), ("left", y_l, WEIGHT_N - right))
        ]
        if monitor.update(float(t), *wrenches):
            return float(t)
    return float(t)


def _monitor(plane: str, target: float, hold_s: float, max_hold_s: float | None) -> HoldMonitor:
    mounts = feet_from_mapping(FEET)
    return HoldMonitor(
        plane, target, T_STEP_S, 0.4, hold_s, max_hold_s, mounts, support_polygon(plane),
        get_robot("teo").contact_force_threshold_n,
    )  # fmt: skip


def _step(target: float, rate_m_s: float = 0.0):
    return lambda t: 0.0 if t < 0 else target * (1.0 - np.exp(-t / 0.2)) + rate_m_s * t


def test_a_settled_zmp_ends_the_hold_at_the_first_check() -> None:
    monitor = _monitor("frontal", 0.05, 3.0, 20.0)
    end = _feed(monitor, "frontal", _step(0.05), 30.0)
    assert monitor.end is not None
    assert monitor.end.kind == "settled"
    assert end - T_STEP_S == pytest.approx(3.0, abs=0.01)


def test_a_fixed_hold_is_not_ended_by_settling() -> None:
    monitor = _monitor("frontal", 0.05, 3.0, None)
    end = _feed(monitor, "frontal", _step(0.05), 4.0)
    assert monitor.end is None
    assert monitor.finish(end).kind == "hold"
    assert monitor.end_time_s == pytest.approx(T_STEP_S + 3.0)


def test_a_creep_is_held_to_the_limit_and_reported_with_its_rate() -> None:
    monitor = _monitor("frontal", 0.05, 3.0, 8.0)  # 0.5 mm/s: 5 mm in the 10 s horizon
    _feed(monitor, "frontal", _step(0.05, 5e-4), 30.0)
    assert monitor.end is not None
    assert monitor.end.kind == "hold_limit"
    assert monitor.end.hold_s == pytest.approx(8.0, abs=0.01)
    assert monitor.end.note.startswith("did not settle within 8 s (drift 0.5")
    assert "drifting" in monitor.end.note


def test_a_creep_toward_the_toe_ends_the_trial_before_the_edge() -> None:
    _, high = support_polygon("sagittal")
    monitor = _monitor("sagittal", 0.08, 3.0, 60.0)
    _feed(monitor, "sagittal", _step(0.08, 0.01), 60.0)  # 10 mm/s toward the toe
    assert monitor.end is not None
    assert monitor.end.kind == "tipping"
    reached = 0.08 + 0.01 * monitor.end.hold_s  # from the standing ZMP, 0 m
    assert TIP_EDGE_FRACTION * high < reached < high
    assert "support edge" in monitor.end.note


def test_a_robot_standing_near_its_heel_edge_is_not_tipping() -> None:
    """The Unitree H1 stands with its ZMP 12 mm in front of its heel edge, 0.193 m behind
    its toe edge (world); a 3 mm lean forwards is no tipping (it once was: the edge was
    judged from the polygon's centre, 9 cm ahead of where the robot stands)."""
    polygon = (-0.012, 0.193)
    mounts = feet_from_mapping(FEET)
    threshold = get_robot("teo").contact_force_threshold_n  # the feet fed are TEO's
    monitor = HoldMonitor("sagittal", 0.003, T_STEP_S, 0.4, 3.0, 20.0, mounts, polygon, threshold)
    _feed(monitor, "sagittal", _step(0.003), 30.0)
    assert monitor.end is not None
    assert monitor.end.kind == "settled"
    behind = HoldMonitor("sagittal", -0.011, T_STEP_S, 0.4, 3.0, 20.0, mounts, polygon, threshold)
    _feed(behind, "sagittal", _step(-0.011), 30.0)
    assert behind.end is not None
    assert behind.end.kind == "tipping"  # 11 mm back: past 85 % of the 12 mm to the heel


def test_a_foot_about_to_lift_ends_a_frontal_trial() -> None:
    monitor = _monitor("frontal", 0.10, 3.0, 60.0)
    _feed(monitor, "frontal", _step(0.10, 0.002), 60.0)  # creeps toward the left foot
    assert monitor.end is not None
    assert monitor.end.kind == "tipping"
    assert "the right foot carries" in monitor.end.note
    y_l, y_r = FEET["left"]["position"][1], FEET["right"]["position"][1]
    lift_at = y_l - LIFT_LOAD_FRACTION * (y_l - y_r)  # right foot below 2 % of the weight
    assert 0.10 + 0.002 * monitor.end.hold_s == pytest.approx(lift_at, abs=0.002)
