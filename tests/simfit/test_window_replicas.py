"""Replicas of a walk log's windows, re-cut from the replica's own sensors.

The references are the simulator's own replay of the same window
(:func:`~zmpkit.simfit.shooting.simulate_window`: the same start, commands and noise seed
must give the same scored readings) and the data's log (what precedes the replay is the
data's, row for row).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_log import WALK_LOG_FILE, walk_log_from_record, write_walk_log
from zmpkit.robots.registry import get_robot
from zmpkit.sensors.imu import quaternion_pitch_roll
from zmpkit.simfit.adequacy import REPLICA_SEED
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.shooting import simulate_window
from zmpkit.simfit.shooting_window import REPLICA_LEADS, ShootingWindow
from zmpkit.simfit.truth_doc import base_truth_path, load_robot_truth, load_truth_doc
from zmpkit.simfit.window_replicas import replayable_windows, replayed_readings, window_replica

NAO = get_robot("nao")
EFFECTS = "M,G,S"
PARAMS = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
DELTA = NAO.description(EFFECTS).sensor_params.encoder_resolution
"""The encoder quantum [rad]."""


@pytest.fixture(scope="module")
def problem(tmp_path_factory: pytest.TempPathFactory) -> FitProblem:
    """The fit problem of a 3 s NAO ``zmpip`` walk's log alone (no walk folder beside it)."""
    config = WalkConfig(
        robot=NAO, speed_mps=0.2, duration_s=3.0, effects=EFFECTS, seed=3, figures=False,
        controller="zmpip",
    )  # fmt: skip
    path = tmp_path_factory.mktemp("log") / WALK_LOG_FILE
    write_walk_log(path, walk_log_from_record(run_walk_trial(config).record))
    experiments = read_experiments([path], NAO)
    base = load_truth_doc(base_truth_path(NAO, None))
    return FitProblem(NAO, EFFECTS, PARAMS, base, tuple(experiments))


def _windows_of(problem: FitProblem) -> list[ShootingWindow]:
    windows = [w for w in problem.experiments if isinstance(w, ShootingWindow)]
    assert len(windows) == len(problem.experiments)
    return windows


def _windows(problem: FitProblem) -> list[ShootingWindow]:
    windows = _windows_of(problem)
    assert len(windows) >= 3
    return windows


def _truth():
    return load_robot_truth(NAO, load_truth_doc(base_truth_path(NAO, None)))


@pytest.mark.parametrize("k", [0, 3])
@pytest.mark.slow
def test_a_replica_window_is_measured_by_the_replays_own_sensors(
    problem: FitProblem, k: int
) -> None:
    """Its scored rows are the simulator's replay of the same lead with the same seed; its
    start is the replay's reading at the window's first row; before the replay the data's."""
    nominal = [p.nominal for p in PARAMS]
    replica = window_replica(problem, nominal, k)
    assert replica is not None
    assert replayable_windows(replica)
    data, again = _windows(problem), _windows(replica)
    assert [w.name for w in again] == [w.name for w in data]
    for window, copy in zip(data[1:], again[1:], strict=True):
        lead = window.replicas[k % len(window.replicas)]
        lead_s = window.command_time_s[0] - lead.command_time_s[0]
        row_s = window.command_time_s[1] - window.command_time_s[0]
        asked = REPLICA_LEADS[k % len(REPLICA_LEADS)] * window.burn_in_s
        assert asked - row_s < lead_s <= asked + 1e-9
        replay = simulate_window(lead, _truth(), EFFECTS, REPLICA_SEED + k)
        np.testing.assert_array_equal(copy.signals.time_s, window.signals.time_s)
        np.testing.assert_array_equal(copy.signals.q_meas_rad, replay.q_meas_rad)
        np.testing.assert_allclose(copy.signals.zmp_m, replay.zmp_m, atol=1e-12)
        np.testing.assert_allclose(copy.signals.force_z_n, replay.force_z_n, atol=1e-9)
        np.testing.assert_allclose(copy.signals.trunk_tilt_rad, replay.trunk_tilt_rad, atol=1e-12)
        np.testing.assert_array_equal(copy.q_cmd_rad, window.q_cmd_rad)
        readings = replayed_readings(lead, _truth(), EFFECTS, REPLICA_SEED + k)
        assert readings is not None
        row = int(np.searchsorted(readings.time_s, window.command_time_s[0] - 1e-9))
        np.testing.assert_array_equal(copy.start.q_rad, readings.q_enc_rad[row])
        np.testing.assert_array_equal(copy.start.imu_quat_wxyz, readings.imu_quat_wxyz[row])
        np.testing.assert_array_equal(copy.start.wrenches[0], readings.right_wrench[row])
        np.testing.assert_array_equal(copy.start.wrenches[1], readings.left_wrench[row])
        # the load history: the data's rows before the lead's start, the replay's after
        history, data_history = copy.start.history, window.start.history
        assert history is not None
        assert data_history is not None
        np.testing.assert_array_equal(history.time_s, data_history.time_s)
        replayed = history.time_s > lead.command_time_s[0] + 1e-9
        np.testing.assert_array_equal(history.wrenches[~replayed], data_history.wrenches[~replayed])
        rows = np.searchsorted(readings.time_s, history.time_s[replayed] - 1e-9)
        assert rows.min() >= 1  # the replay's own readings, not the start it began from
        np.testing.assert_array_equal(history.q_rad[replayed], readings.q_enc_rad[rows])
        # the drives' integrals: the data's steps up to the lead's start, the replay's after
        steps, data_steps = copy.start.error_steps_rad_s, window.start.error_steps_rad_s
        assert steps.shape == data_steps.shape
        before = lead.start.error_steps_rad_s.shape[0]
        np.testing.assert_array_equal(steps[:before], data_steps[:before])


@pytest.mark.slow
def test_a_replica_by_the_robot_that_walked_starts_within_its_sensor_noise(
    problem: FitProblem,
) -> None:
    """The truth replaying its own log from 0.3 s earlier: the same starts to a few encoder
    quanta, and the log's first window (no earlier state) from its own measured state."""
    nominal = [p.nominal for p in PARAMS]
    replica = window_replica(problem, nominal, 0)
    assert replica is not None
    data, again = _windows(problem), _windows(replica)
    for window, copy in zip(data, again, strict=True):
        assert np.max(np.abs(copy.start.q_rad - window.start.q_rad)) <= 4 * DELTA + 1e-12
        assert np.max(np.abs(copy.signals.q_meas_rad - window.signals.q_meas_rad)) < 0.02
    # a window with no earlier state (a log's first) is replayed from its own measured start
    first = replace(data[1], replicas=())
    lone = window_replica(replace(problem, experiments=(first,)), nominal, 0)
    assert lone is not None
    (copy,) = _windows_of(lone)
    np.testing.assert_array_equal(copy.start.q_rad, first.start.q_rad)
    np.testing.assert_array_equal(copy.start.error_steps_rad_s, first.start.error_steps_rad_s)


def test_a_replay_that_falls_is_left_out(problem: FitProblem) -> None:
    """Started pitched past the fall tilt, the replay reads a fall and gives no rows."""
    window = _windows(problem)[1]
    pitch = 1.0
    tilted = np.array([np.cos(pitch / 2), 0.0, np.sin(pitch / 2), 0.0])
    assert quaternion_pitch_roll(tilted)[0] == pytest.approx(pitch)
    fallen = replace(window, start=replace(window.start, imu_quat_wxyz=tilted))
    assert replayed_readings(fallen, _truth(), EFFECTS, REPLICA_SEED) is None
    kept = replayed_readings(window, _truth(), EFFECTS, REPLICA_SEED)
    assert kept is not None
    assert kept.time_s.size == window.command_time_s.size


def test_only_a_problem_of_log_windows_is_replayable(problem: FitProblem) -> None:
    assert replayable_windows(problem)
    assert not replayable_windows(replace(problem, experiments=()))


def test_the_log_file_is_where_the_replica_says_it_came_from(problem: FitProblem) -> None:
    replica = window_replica(problem, [p.nominal for p in PARAMS], 1)
    assert replica is not None
    sources = {w.source for w in _windows(replica)}
    assert sources == {w.source for w in _windows(problem)}
    assert Path(next(iter(sources))).name == WALK_LOG_FILE
