"""Walks with feedback, pushes and honest outcomes (falls, stalls, nulls)."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.experiments import walk_trial
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_disturbances import Push
from zmpkit.experiments.walk_summary import stall_time, summarise_walk
from zmpkit.robots.registry import get_robot

NAO = get_robot("nao")

METRICS = (
    "mean_speed_mps", "planned_speed_mps", "trunk_pitch_peak_hz",
    "trunk_pitch_peak_amplitude_rad", "trunk_pitch_std_rad",
    "trunk_pitch_step_frequency_amplitude_rad", "mean_double_support_foot_distance_m",
    "planned_double_support_foot_distance_m", "foot_slip_m", "foot_slip_x_m",
)  # fmt: skip


def test_a_push_is_read_from_the_command_line_form() -> None:
    assert Push.parse("20@4.5:-y") == Push(20.0, 4.5, "-y")
    assert Push.parse("10@3") == Push(10.0, 3.0, "x")
    assert Push(10.0, 3.0, "y").force_in_world(3.05) == (0.0, 10.0)
    assert Push(10.0, 3.0, "y").force_in_world(3.1) == (0.0, 0.0)
    for bad in ("20", "x@3", "20@3:z", "-5@3", "20@-1"):
        with pytest.raises(ParameterError, match=r"push|Push"):
            Push.parse(bad)


def test_an_unknown_controller_is_refused() -> None:
    with pytest.raises(ParameterError, match="controller must be one of zmpip, dcm, open"):
        WalkConfig(NAO, controller="mpc")


@pytest.fixture(scope="module")
def pushed_over():
    """The rigid robot, open loop, pushed sideways by 40 N for 0.1 s."""
    config = WalkConfig(
        NAO,
        effects="none", duration_s=3.0, controller="open", figures=False,
        pushes=(Push(40.0, 1.5, "y"),),
    )  # fmt: skip
    return run_walk_trial(config)


def test_a_sideways_push_is_a_roll_fall_with_every_metric_null(pushed_over) -> None:
    s = pushed_over.summary
    assert s.fell
    assert s.fall_kind == "roll"
    assert s.fall_time_s == pytest.approx(pushed_over.record.time_s[-1])
    assert 1.5 < s.fall_time_s < 3.0
    assert all(getattr(s, name) is None for name in METRICS)
    assert s.pushes == ("40@1.5:y",)
    assert pushed_over.record.fall_kind == "roll"


@pytest.fixture(scope="module")
def rigid_walk():
    return run_walk_trial(WalkConfig(NAO, effects="none", duration_s=4.0, controller="open"))


def test_the_fall_height_is_a_share_of_the_robot_s_own_starting_height(monkeypatch) -> None:
    """Not an absolute height: a rule at 101 % of the posed torso fires at once (``height``),
    the default 60 % never on a walk that stands, whatever the robot's size."""
    config = WalkConfig(NAO, effects="none", duration_s=1.0, controller="open")
    monkeypatch.setattr(walk_trial, "FALL_TORSO_HEIGHT_FRACTION", 1.01)
    record = run_walk_trial(config).record
    assert record.fall_kind == "height"
    assert record.time_s.size <= 3
    monkeypatch.setattr(walk_trial, "FALL_TORSO_HEIGHT_FRACTION", 0.6)
    record = run_walk_trial(config).record
    assert not record.fell
    assert record.torso_in_world[:, 2].min() > 0.6 * record.torso_in_world[0, 2]


@pytest.mark.slow
def test_a_walk_that_stays_in_place_is_a_stall(rigid_walk) -> None:
    """Motion capture of a robot stepping on the spot: no progress over two steps."""
    record = rigid_walk.record
    assert stall_time(rigid_walk.pattern, record) is None
    frozen = np.repeat(record.torso_in_world[:1], record.time_s.size, axis=0)
    stalled = dataclasses.replace(record, torso_in_world=frozen)
    when = stall_time(rigid_walk.pattern, stalled)
    window = rigid_walk.summary.window_s
    assert when is not None
    assert window[0] < when <= window[1]
    s = summarise_walk(rigid_walk.pattern, rigid_walk.trajectory, stalled, "", 0)
    assert s.fell
    assert s.fall_kind == "stall"
    assert s.fall_time_s == when
    assert all(getattr(s, name) is None for name in METRICS)


def test_half_the_commanded_progress_is_not_a_stall(rigid_walk) -> None:
    """The rule's boundary: at 60 % of the commanded progress the walk is slow, not stalled."""
    record = rigid_walk.record
    torso = record.torso_in_world.copy()
    torso[:, 0] = 0.6 * 0.2 * record.time_s
    slow = dataclasses.replace(record, torso_in_world=torso)
    assert stall_time(rigid_walk.pattern, slow) is None
    torso[:, 0] = 0.4 * 0.2 * record.time_s
    assert stall_time(rigid_walk.pattern, dataclasses.replace(record, torso_in_world=torso))


@pytest.mark.slow
def test_zmpip_recovers_from_a_20_n_push_that_fells_the_open_loop_walk() -> None:
    """All effects on, a 4 s walk pushed backwards with 20 N for 0.1 s at 2.2 s."""
    push = (Push(20.0, 2.2, "-x"),)
    outcomes = {
        controller: run_walk_trial(
            WalkConfig(NAO, duration_s=4.0, controller=controller, figures=False, pushes=push)
        ).summary
        for controller in ("open", "zmpip")
    }
    assert outcomes["open"].fell
    assert not outcomes["zmpip"].fell
    assert outcomes["zmpip"].controller == "zmpip"
    assert outcomes["zmpip"].mean_speed_mps == pytest.approx(0.2, abs=0.03)


@pytest.mark.slow
def test_feedback_does_not_shake_a_rigid_robot() -> None:
    """Every effect off, 0.2 m/s, 0.5 s steps, 10 s: the ZMP/IP walk's step-frequency trunk
    oscillation stays within 1.5 times the open-loop walk's (it was 3.2 times, reading the
    legs' own multibody ZMP and the feet's landings as disturbances)."""
    amplitude = {
        controller: run_walk_trial(
            WalkConfig(NAO, controller=controller, effects="none", figures=False)
        ).summary.trunk_pitch_step_frequency_amplitude_rad
        for controller in ("open", "zmpip")
    }
    assert amplitude["open"] is not None
    assert amplitude["zmpip"] is not None
    assert amplitude["zmpip"] <= 1.5 * amplitude["open"]


@pytest.mark.slow
@pytest.mark.parametrize(
    "change",
    [{"speed_mps": 0.25}, {"step_duration_s": 0.4}, {"speed_mps": 0.0, "lateral_speed_mps": 0.05}],
)
def test_zmpip_walks_where_the_open_loop_walk_falls(change) -> None:
    """Paper B's robot (all effects) outside the one tuned walk: 10 s each."""
    open_loop = run_walk_trial(WalkConfig(NAO, controller="open", figures=False, **change)).summary
    closed = run_walk_trial(WalkConfig(NAO, controller="zmpip", figures=False, **change)).summary
    assert open_loop.fell
    assert not closed.fell


def _truth_with_gain_factor(tmp_path, factor: float):
    """The shipped NAO truth with MoToFlex's fitted PID (p 319.47 V/rad, d 1.6356 V·s/rad)
    scaled by ``factor`` (the shipped file is ×4 on p and ×6 on d)."""
    text = get_robot("nao").truth.default_path.read_text(encoding="utf-8")
    text, n_p = re.subn(r"(?m)^  p: [0-9.]+", f"  p: {319.47 * factor:.3f}", text)
    text, n_d = re.subn(r"(?m)^  d: [0-9.]+", f"  d: {1.6356 * factor:.5f}", text)
    assert (n_p, n_d) == (1, 1)
    path = tmp_path / f"truth_x{factor:g}.yaml"
    path.write_text(text, encoding="utf-8")
    return str(path)


@pytest.mark.slow
def test_with_feedback_the_robot_walks_on_motoflex_s_own_gains(tmp_path) -> None:
    """The servo gains the open-loop replay needs (×4) are not needed with feedback: on
    MoToFlex's fitted gains (×1) zmpip walks 10 s where the open loop falls (slower than
    commanded: the servos lag); at ×1.5 at the commanded speed."""
    speeds = {}
    for factor in (1.0, 1.5):
        truth = _truth_with_gain_factor(tmp_path, factor)
        outcomes = {
            controller: run_walk_trial(
                WalkConfig(NAO, controller=controller, truth=truth, figures=False)
            ).summary
            for controller in ("open", "zmpip")
        }
        assert outcomes["open"].fell
        assert not outcomes["zmpip"].fell
        speeds[factor] = outcomes["zmpip"].mean_speed_mps
    assert speeds[1.0] == pytest.approx(0.2, abs=0.03)
    assert speeds[1.5] == pytest.approx(0.2, abs=0.01)


def test_a_command_past_the_longest_step_is_walked_shorter_and_says_so() -> None:
    """0.3 m/s at 0.5 s steps asks 0.15 m steps of a robot whose limit is 0.12 m: accepted
    (up to twice the limit) with the clamp named; three times the limit is refused."""
    plan = WalkConfig(NAO, speed_mps=0.3).pattern_config().plan()
    assert plan.clamped_limits == ("step_length",)
    assert not WalkConfig(NAO, speed_mps=0.2).pattern_config().plan().clamped_limits
    with pytest.raises(ParameterError, match=r"must lie in \[0\.0, 0\.48\] m/s"):
        WalkConfig(NAO, speed_mps=0.72)
