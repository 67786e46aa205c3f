"""Walk logs fitted by multiple shooting: the log, the measured start state, the replay.

The independent reference is the simulator itself: a NAO ``zmpip`` walk (M, G, S, the
shipped truth) is recorded by ``zmpkit walk``'s own loop; its log holds only sensor
readings, and the tests compare what the windows reconstruct from them with the
simulator's hidden state (``record.qpos``), which only tests read.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_log import (
    WALK_LOG_FILE,
    WalkLog,
    read_walk_log,
    walk_log_from_record,
    write_walk_log,
)
from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.cost import CostWeights, experiment_cost
from zmpkit.simfit.experiments import WalkExperiment, read_experiments
from zmpkit.simfit.open_loop import is_open_loop
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.problem import FitProblem, evaluate
from zmpkit.simfit.shooting import simulate_window, start_window
from zmpkit.simfit.shooting_window import (
    DEFAULT_BURN_IN_S,
    DEFAULT_WINDOW_S,
    LOAD_HISTORY_S,
    SLOPE_ROWS,
    ShootingWindow,
    log_fall_time,
    log_windows,
)
from zmpkit.simfit.truth_doc import base_truth_path, load_robot_truth, load_truth_doc
from zmpkit.simfit.walk_plan import FALL_MARGIN_S

NAO = get_robot("nao")
EFFECTS = "M,G,S"
DELTA = NAO.description(EFFECTS).sensor_params.encoder_resolution
"""The encoder quantum [rad]: the noise of every joint angle the log holds."""


@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> tuple[WalkRecord, Path]:
    """A 3 s NAO zmpip walk (about 5.6 s recorded) and its log written as CSV."""
    config = WalkConfig(
        robot=NAO, speed_mps=0.2, duration_s=3.0, effects=EFFECTS, seed=3, figures=False,
        controller="zmpip",
    )  # fmt: skip
    record = run_walk_trial(config).record
    path = tmp_path_factory.mktemp("log") / WALK_LOG_FILE
    write_walk_log(path, walk_log_from_record(record))
    return record, path


@pytest.fixture(scope="module")
def windows(walk: tuple[WalkRecord, Path]) -> list[ShootingWindow]:
    return log_windows(read_walk_log(walk[1]), NAO, "walk")


def _truth():
    return load_robot_truth(NAO, load_truth_doc(base_truth_path(NAO, None)))


@pytest.mark.slow
def test_the_log_holds_the_sensor_readings_only(walk: tuple[WalkRecord, Path], tmp_path) -> None:
    record, path = walk
    log = read_walk_log(path)
    assert log.joint_names == record.joint_names
    assert np.allclose(log.q_enc_rad, record.q_meas_rad, atol=1e-9)
    assert np.allclose(log.q_cmd_rad, record.q_cmd_rad, atol=1e-9)
    header = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    prefixes = ("time", "cmd_", "enc_", "imu_", "right_", "left_")
    assert all(c.startswith(prefixes) for c in header)
    parquet = write_walk_log(tmp_path / "log.parquet", log)
    again = read_walk_log(parquet)
    assert np.array_equal(again.q_enc_rad, log.q_enc_rad)
    assert np.array_equal(again.left_wrench, log.left_wrench)


@pytest.mark.slow
def test_a_log_without_a_column_is_one_clear_error(walk: tuple[WalkRecord, Path], tmp_path) -> None:
    lines = walk[1].read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    drop = header.index("left_fz")
    bad = tmp_path / "bad.csv"
    bad.write_text(
        "\n".join(",".join(c for k, c in enumerate(r.split(",")) if k != drop) for r in lines),
        encoding="utf-8",
    )
    with pytest.raises(InputFileError, match="missing columns \\['left_fz'\\]"):
        read_experiments([bad], NAO)
    lines[5] = lines[5].replace(lines[5].split(",")[1], "abc", 1)
    bad.write_text("\n".join(lines), encoding="utf-8")
    with pytest.raises(InputFileError, match="expected 45 numbers per row"):
        read_experiments([bad], NAO)


def test_the_start_state_is_the_simulators_within_the_sensor_noise(
    walk: tuple[WalkRecord, Path], windows: list[ShootingWindow]
) -> None:
    """Tolerances from the sensors: encoder quantum δ, IMU one physics step late.

    - joint angles: a quantised encoder is within δ/2 of the motor angle;
    - joint speeds, against the same centred slope of the true angles: the quantisation
      moves a 5-row slope by at most (δ/2) Σ|t_i - t̄| / Σ(t_i - t̄)² = 0.3 δ / T;
    - base orientation: MuJoCo's IMU reads the state before the step, so it lags by one
      step dt: at most dt times the trunk's largest rate;
    - base height and speed: the stance leg's six joints at δ/2 (and their speeds at
      0.3 δ/T) over the NAO's leg (< 0.35 m lever): 6 · 0.35 · δ/2 and 6 · 0.35 · 0.3 δ/T.
    """
    record = walk[0]
    sim0 = NAO.make_simulation(EFFECTS, _truth())
    qadr = [int(sim0.model.joint(j).qposadr[0]) for j in sim0.joint_names]
    dof = [int(sim0.model.joint(j).dofadr[0]) for j in sim0.joint_names]
    period = float(np.median(np.diff(record.time_s)))
    speed_tol = 0.3 * DELTA / period
    rate = float(np.max(np.linalg.norm(record.sensors.gyro_rps, axis=1)))
    assert len(windows) >= 3
    for window in windows:
        sim = NAO.make_simulation(EFFECTS, _truth())
        start_window(window, sim)
        r = int(np.argmin(np.abs(record.time_s - window.command_time_s[0])))
        true = record.qpos[r]
        data = sim.data
        assert np.max(np.abs(data.qpos[qadr] - true[qadr])) <= DELTA / 2 + 1e-9
        rows = slice(r - SLOPE_ROWS // 2, r + SLOPE_ROWS // 2 + 1)
        t = record.time_s[rows] - record.time_s[rows].mean()
        true_slope = t @ (record.qpos[rows][:, qadr] - record.qpos[rows][:, qadr].mean(0))
        assert np.max(np.abs(data.qvel[dof] - true_slope / (t @ t))) <= speed_tol + 1e-9
        angle = 2.0 * math.acos(min(1.0, abs(float(data.qpos[3:7] @ true[3:7]))))
        assert angle <= sim.dt * rate + 1e-6
        assert abs(data.qpos[2] - true[2]) <= 6 * 0.35 * DELTA / 2
        h = record.time_s[r + 1] - record.time_s[r - 1]
        base_speed = (record.qpos[r + 1, :3] - record.qpos[r - 1, :3]) / h
        assert np.max(np.abs(data.qvel[:3] - base_speed)) <= 6 * 0.35 * speed_tol


@pytest.mark.slow
def test_the_true_parameters_replay_the_log_to_its_noise_and_a_wrong_one_does_not(
    windows: list[ShootingWindow],
) -> None:
    """Two quantised encoders of the same motion differ by √2 δ/√12 RMS: the noise floor."""
    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(NAO, None))
    problem = FitProblem(NAO, EFFECTS, params, doc, tuple(windows))
    nominal = np.array([p.nominal for p in params])

    def costs(values: np.ndarray) -> tuple[float, float]:
        terms = [evaluate(problem, values, i) for i in range(len(windows))]
        cost = float(np.mean([t.total(CostWeights()) for t in terms]))
        return cost, float(np.mean([t.joint_rms_rad for t in terms]))

    floor_rms = math.sqrt(2.0) * DELTA / math.sqrt(12.0)
    cost, rms = costs(nominal)
    assert rms <= floor_rms
    wrong_cost, wrong_rms = costs(nominal * np.array([1.25, 1.0]))
    assert wrong_rms > floor_rms
    assert wrong_cost > 3.0 * cost


def test_a_window_replays_the_same_serially_as_through_the_fit(
    windows: list[ShootingWindow],
) -> None:
    window = windows[1]
    a = simulate_window(window, _truth(), EFFECTS)
    b = simulate_window(window, _truth(), EFFECTS)
    assert a.time_s.size == window.signals.time_s.size
    assert np.array_equal(a.q_meas_rad, b.q_meas_rad)
    assert experiment_cost(window.signals, a).completed == 1.0
    assert not is_open_loop(window)


def test_windows_tile_the_log_and_stop_before_a_fall(
    walk: tuple[WalkRecord, Path], windows: list[ShootingWindow]
) -> None:
    scored = DEFAULT_WINDOW_S - DEFAULT_BURN_IN_S
    starts = [w.signals.time_s[0] for w in windows]
    gaps = np.diff(starts)  # whole scored spans apart (standing windows dropped), to a row
    spans = np.round(gaps / scored)
    assert np.all(spans >= 1)
    assert np.max(np.abs(gaps - spans * scored)) <= 0.0101
    log = read_walk_log(walk[1])
    fall_row = int(np.searchsorted(log.time_s, 3.5))
    quat = log.imu_quat_wxyz.copy()
    tipped = np.array([math.cos(0.45), 0.0, math.sin(0.45), 0.0])  # 0.9 rad of pitch
    quat[fall_row:] = tipped
    fallen = WalkLog(
        log.time_s, log.joint_names, log.q_cmd_rad, log.q_enc_rad, quat, log.gyro_rps,
        log.right_wrench, log.left_wrench, log.accel_mps2,
    )  # fmt: skip
    fall = log_fall_time(fallen)
    assert fall == pytest.approx(log.time_s[fall_row])
    cut = log_windows(fallen, NAO, "fell")
    assert cut
    assert max(w.signals.time_s[-1] for w in cut) <= fall - FALL_MARGIN_S + 1e-9


def test_a_window_starts_with_the_load_history_of_the_rows_before_it(
    walk: tuple[WalkRecord, Path], windows: list[ShootingWindow]
) -> None:
    """Each start carries the log's rows of the LOAD_HISTORY_S before it, as read (the stance
    the foot with the larger F_z)."""
    log = read_walk_log(walk[1])
    for window in windows:
        history, start_s = window.start.history, window.command_time_s[0]
        assert history is not None
        rows = (log.time_s >= start_s - LOAD_HISTORY_S - 1e-9) & (log.time_s < start_s - 1e-9)
        np.testing.assert_array_equal(history.time_s, log.time_s[rows])
        np.testing.assert_array_equal(history.wrenches[:, 0], log.right_wrench[rows])
        np.testing.assert_array_equal(history.wrenches[:, 1], log.left_wrench[rows])
        left_loaded = log.left_wrench[rows, 2] > log.right_wrench[rows, 2]
        assert history.stance.tolist() == left_loaded.astype(int).tolist()
        assert history.q_rad.shape == history.dq_rad_s.shape == (rows.sum(), len(log.joint_names))


@pytest.mark.slow
def test_a_walk_that_fell_is_fitted_up_to_its_fall() -> None:
    """A push the log does not hold tips the NAO over; the log alone says when."""
    from zmpkit.experiments.walk_trial import Push

    config = WalkConfig(
        robot=NAO, speed_mps=0.2, duration_s=6.0, effects=EFFECTS, figures=False,
        pushes=(Push.parse("30@3:x"),),
    )  # fmt: skip
    record = run_walk_trial(config).record
    assert record.fall_time_s is not None
    log = walk_log_from_record(record)
    assert log_fall_time(log) == pytest.approx(record.fall_time_s)
    windows = log_windows(log, NAO, "fell")
    assert windows
    assert max(w.signals.time_s[-1] for w in windows) <= record.fall_time_s - FALL_MARGIN_S


def test_a_log_of_other_joints_is_refused_and_one_without_gyro_is_read(
    walk: tuple[WalkRecord, Path], tmp_path: Path
) -> None:
    log = read_walk_log(walk[1])
    fewer = WalkLog(
        log.time_s, log.joint_names[1:], log.q_cmd_rad[:, 1:], log.q_enc_rad[:, 1:],
        log.imu_quat_wxyz, log.gyro_rps, log.right_wrench, log.left_wrench,
    )  # fmt: skip
    with pytest.raises(InputFileError, match="driven joints"):
        log_windows(fewer, NAO, "fewer")
    blind = WalkLog(
        log.time_s, log.joint_names, log.q_cmd_rad, log.q_enc_rad, log.imu_quat_wxyz, None,
        log.right_wrench, log.left_wrench,
    )  # fmt: skip
    path = write_walk_log(tmp_path / "blind.parquet", blind)
    windows = read_experiments([path], NAO)
    with_gyro = log_windows(log, NAO, "walk")
    assert len(windows) == len(with_gyro)
    for a, b in zip(windows, with_gyro, strict=True):
        assert isinstance(a, ShootingWindow)
        # the orientation's central difference over two rows against the gyro: the gyro's
        # noise at five standard deviations (the difference's own error is smaller)
        noise = NAO.description(EFFECTS).sensor_params.gyro_noise_std
        assert np.max(np.abs(a.start.gyro_rps - b.start.gyro_rps)) < 5.0 * noise


def test_bad_windows_are_one_clear_error(walk: tuple[WalkRecord, Path]) -> None:
    log = read_walk_log(walk[1])
    with pytest.raises(ParameterError, match="longer than its burn-in"):
        log_windows(log, NAO, "walk", 0.2, 0.3)
    with pytest.raises(InputFileError, match="no window of 60 s"):
        log_windows(log, NAO, "walk", 60.0)
    with pytest.raises(InputFileError, match="walk log"):
        read_experiments([walk[1].parent / "missing.csv"], NAO)


def test_a_folder_with_a_log_and_no_summary_reads_as_windows(
    walk: tuple[WalkRecord, Path],
) -> None:
    experiments = read_experiments([walk[1].parent], NAO)
    assert experiments
    assert all(isinstance(e, ShootingWindow) for e in experiments)


@pytest.mark.slow
def test_zmpkit_walk_writes_the_log_and_identify_sim_fits_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The CLI end to end: ``zmpkit walk`` writes walk_log.csv, ``identify sim`` fits it.

    With ``--interval-replicas 0`` its intervals are the noise-only ones, and every output
    says so (the bias-corrected ones: ``test_pipeline_replicas``).
    """
    from zmpkit.cli.app import main

    walk = tmp_path / "walk"
    argv = ["walk", "--robot", "nao", "--duration", "3", "--effects", "M,G,S", "--no-video"]
    assert main([*argv, "--report", "md", "--out", str(walk)]) == 0
    header = (walk / WALK_LOG_FILE).read_text(encoding="utf-8").splitlines()[0]
    assert "torso" not in header
    assert "zmp" not in header
    fit = tmp_path / "fit"
    argv = ["identify", "sim", str(walk / WALK_LOG_FILE), "--robot", "nao", "--quick"]
    argv += ["--generations", "1", "--popsize", "4", "--workers", "1", "--report", "md"]
    capsys.readouterr()
    assert main([*argv, "--interval-replicas", "0", "--out", str(fit)]) == 0
    assert "intervals: noise only" in capsys.readouterr().out
    report = (fit / "report.md").read_text(encoding="utf-8")
    assert "fitted by multiple shooting with" in report
    assert "The 95 % intervals: noise only" in report
    fitted = yaml.safe_load((fit / "fitted_parameters.yaml").read_text(encoding="utf-8"))
    for entry in fitted["parameters"].values():
        assert entry["interval_95_method"].startswith("noise only")
        assert entry["estimator_bias_pct"] is None
    assert (fit / "intervals.csv").read_text(encoding="utf-8").count("noise_only") == 2
    (own,) = read_experiments([walk], NAO)  # a walk folder still reads as zmpkit's own walk
    assert isinstance(own, WalkExperiment)
    assert own.closed_loop is not None


@pytest.mark.slow
def test_a_closed_loop_walk_is_recovered_from_its_log_alone(tmp_path: Path) -> None:
    """Self-test: a zmpip walk of a NAO with hidden PID scale and gear stiffness, its
    controller unknown to the fit, fitted by multiple shooting from its sensor log.

    Its intervals come from the log's windows replayed again and re-fitted (the log has no
    walk folder to walk again). Measured (seed 1: truth 0.7968 and 1424 N·m/rad; 11
    windows): 0.808 [0.783, 0.831] and 1324 [1218, 1443] N·m/rad, best cost 0.0063 against a
    floor of 0.0062 ± 0.0007.
    The two trade along a valley (a stiffer drive and a softer gear give the same series
    stiffness), so the estimates are bounded at 10 %, beside their intervals.
    """
    from zmpkit.pipelines.identify_sim import IdentifySimConfig, run_identify_sim
    from zmpkit.pipelines.identify_sim_files import write_identify_sim
    from zmpkit.simfit.self_test import perturbed_values
    from zmpkit.simfit.truth_doc import truth_doc_with, write_truth_doc

    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    hidden = perturbed_values(params, 1)
    doc = truth_doc_with(load_truth_doc(base_truth_path(NAO, None)), params, hidden)
    truth = write_truth_doc(doc, tmp_path / "hidden_truth.yaml")
    config = WalkConfig(
        robot=NAO, speed_mps=0.2, duration_s=10.0, effects=EFFECTS, seed=1, figures=False,
        controller="zmpip", truth=str(truth),
    )  # fmt: skip
    record = run_walk_trial(config).record
    log = write_walk_log(tmp_path / WALK_LOG_FILE, walk_log_from_record(record))
    fit_config = IdentifySimConfig(data=(str(log),), robot=NAO, quick=True, workers=1)
    result = write_identify_sim(run_identify_sim(fit_config, tmp_path / "fit"), tmp_path / "fit")
    assert "multiple shooting" in result.files["report"].read_text(encoding="utf-8")
    intervals = {i.name: i for i in result.intervals}
    for p, true in zip(params, hidden, strict=True):
        fitted, interval = result.fitted[p.name], intervals[p.name]
        assert interval.kind == "window_refits"
        assert interval.lower <= true <= interval.upper, (p.name, fitted, true, interval)
        assert abs(fitted - true) / true < 0.10, (p.name, fitted, true)
    assert result.adequacy is not None
    assert result.adequacy.explains, result.adequacy.verdict
