"""Simulator fit, the parts without a fit: parameters, truth paths, data, cost, errors."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.ndimage import uniform_filter1d

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.pipelines.identify_sim import IdentifySimConfig
from zmpkit.robots.registry import get_robot
from zmpkit.simfit import parameters as catalogue
from zmpkit.simfit.checkpoint import check_fingerprint, load_checkpoint
from zmpkit.simfit.cost import (
    FAILED_COST,
    FORCE_SMOOTHING_S,
    ZMP_SMOOTHING_S,
    CostWeights,
    experiment_cost,
)
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.optimizer import CmaOptions, fingerprint
from zmpkit.simfit.outputs import write_fitted_truth
from zmpkit.simfit.parameters import FitParameter, default_parameters
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.self_test import (
    RECOVERY_COLUMNS,
    perturbed_values,
    recovery_rows,
    write_recovery_csv,
)
from zmpkit.simfit.truth_doc import (
    base_truth_path,
    get_path,
    load_truth_doc,
    set_path,
    truth_doc_with,
)
from zmpkit.simfit.walk_plan import FALL_MARGIN_S

NAO = get_robot("nao")
TEO = get_robot("teo")


@given(u=st.floats(0.0, 1.0), log=st.booleans())
def test_normalised_coordinates_round_trip(u: float, log: bool) -> None:
    p = FitParameter("k", "gear.stiffness", 1000.0, 100.0, 10000.0, "N·m/rad", log)
    value = p.from_unit(u)
    assert 100.0 <= value <= 10000.0
    assert p.to_unit(value) == pytest.approx(u, abs=1e-12)


def test_log_scale_midpoint_is_geometric_mean() -> None:
    p = FitParameter("k", "x", 1000.0, 100.0, 10000.0, "N·m/rad", True)
    assert p.from_unit(0.5) == pytest.approx(1000.0)


def test_fit_parameter_rejects_nominal_outside_bounds() -> None:
    with pytest.raises(ParameterError, match=r"nominal 5.0 - is outside \[0.0, 1.0\]"):
        FitParameter("a", "x", 5.0, 0.0, 1.0, "-")


def test_catalogue_names_valid_letters_and_robot_gaps(monkeypatch: pytest.MonkeyPatch) -> None:
    with pytest.raises(ParameterError, match=r"letters from: M .*C \(mass and CoM"):
        default_parameters(NAO, "M,X")
    no_c = default_parameters(NAO, "M,I,G,F,S")
    monkeypatch.setattr(catalogue, "robot_catalogue", lambda robot: no_c)
    with pytest.raises(ParameterError, match="nao has no fit parameters for effect C"):
        default_parameters(NAO, "C")
    with pytest.raises(ParameterError, match="valid: \\['gear_backlash'"):
        default_parameters(NAO, "G", ("nope",))


@pytest.mark.parametrize("robot", ["nao", "teo"])
def test_every_catalogue_path_exists_in_the_shipped_truth(robot: str) -> None:
    doc = load_truth_doc(base_truth_path(get_robot(robot), None))
    # NAO's C starts from the design (the URDF torso), not the shipped truth: see
    # tests/robots/test_nao_payload.py.
    letters = "M,I,G,F,S" + (",C" if robot == "teo" else "")
    for p in default_parameters(get_robot(robot), letters):
        values = get_path(doc, p.path)
        assert values == pytest.approx([p.nominal] * len(values)), p.name


def test_set_path_sets_every_indexed_item_and_names_bad_keys() -> None:
    doc = {"flex": [{"k": [1.0, 0.0]}, {"k": [2.0, 0.0]}, {"k": [3.0, 0.0]}]}
    set_path(doc, "flex[0,2].k[0]", 9.0)
    assert [f["k"][0] for f in doc["flex"]] == [9.0, 2.0, 9.0]
    set_path(doc, "flex[*].k[1]", 5.0)
    assert [f["k"][1] for f in doc["flex"]] == [5.0, 5.0, 5.0]
    with pytest.raises(ParameterError, match="no key 'gear'"):
        set_path(doc, "gear.stiffness", 1.0)
    with pytest.raises(ParameterError, match=r"index \[7\] outside a list of 3"):
        get_path(doc, "flex[7].k[0]")


@pytest.mark.parametrize("robot", ["nao", "teo"])
def test_fitted_truth_is_loadable_as_truth(robot: str, tmp_path: Path) -> None:
    params = default_parameters(get_robot(robot), "G")
    doc = load_truth_doc(base_truth_path(get_robot(robot), None))
    values = [p.from_unit(0.3) for p in params]
    path = write_fitted_truth(tmp_path / "fitted.yaml", doc, params, values, "test")
    if robot == "nao":
        from zmpkit.robots.nao import load_truth
    else:
        from zmpkit.robots.teo import load_truth
    truth = load_truth(path)
    assert truth.gear.stiffness == pytest.approx(values[0])
    assert truth_doc_with(doc, params, values)["gear"]["stiffness"] == pytest.approx(values[0])


def test_recovery_csv_has_exactly_the_columns(tmp_path: Path) -> None:
    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    truth = perturbed_values(params, 3)
    for p, t in zip(params, truth, strict=True):
        assert 0.079 < abs(np.log(t / p.nominal)) < 0.224  # 8-25 % off nominal
    rows = recovery_rows(params, truth, truth * 1.02, [True, False])
    lines = write_recovery_csv(rows, tmp_path / "recovery.csv").read_text().splitlines()
    assert tuple(lines[0].split(",")) == RECOVERY_COLUMNS
    assert lines[0] == "parameter,truth,fitted,error_pct,identifiable"
    assert lines[1].startswith("pid_gain_scale,")
    assert lines[1].endswith(",2,true")
    assert lines[2].endswith(",2,false")


def _signals(n: int, shift: float = 0.0) -> RecordedSignals:
    t = np.arange(n) * 0.01
    q_cmd = np.column_stack([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t)])
    q_meas = q_cmd + 0.01 * np.sin(2 * np.pi * 2 * t)[:, None] + shift
    zmp = np.column_stack([0.1 * t, 0.03 * np.sin(2 * np.pi * 2 * t)])
    tilt = 0.02 * np.sin(2 * np.pi * 2 * t) * (1 + shift)
    return RecordedSignals(t, ("a", "b"), q_cmd, q_meas, zmp, tilt)


def test_cost_is_zero_for_identical_signals_and_grows_with_the_miss() -> None:
    rec = _signals(400)
    same = experiment_cost(rec, rec)
    assert (same.joint, same.zmp, same.spectrum) == (0.0, 0.0, 0.0)
    off = experiment_cost(rec, _signals(400, shift=0.005))
    # encoder offset 0.005 rad vs a recorded tracking error of RMS 0.01/sqrt(2) rad
    assert off.joint == pytest.approx(0.005 / (0.01 / np.sqrt(2)), rel=1e-6)
    assert off.spectrum == pytest.approx(0.005, rel=0.05)
    assert off.total(CostWeights()) > 0.0


def test_a_constant_zmp_shift_costs_only_when_the_mean_is_kept() -> None:
    rec = _signals(400)
    shifted = RecordedSignals(  # a 5 mm shift, as a CoM or F-T moment offset gives
        rec.time_s, rec.joint_names, rec.q_cmd_rad, rec.q_meas_rad,
        rec.zmp_m + np.array([0.004, -0.003]), rec.trunk_tilt_rad,
    )  # fmt: skip
    assert experiment_cost(rec, shifted).zmp == pytest.approx(0.0, abs=1e-12)
    # scale: RMS of the smoothed recorded ZMP about its trend: the y sine, 0.03 / sqrt(2) m,
    # times the moving mean's gain at 2 Hz (w rows: |sin(pi f w dt) / (w sin(pi f dt))|),
    # less the little of 8 sine periods a straight line takes away (0.5 %)
    width = round(ZMP_SMOOTHING_S / 0.01)
    gain = abs(np.sin(np.pi * 2 * width * 0.01) / (width * np.sin(np.pi * 2 * 0.01)))
    kept = experiment_cost(rec, shifted, models_loads=True).zmp
    assert kept == pytest.approx(0.005 / (gain * 0.03 / np.sqrt(2)), rel=0.01)


def test_a_zmp_jump_a_tick_late_costs_the_moving_mean_of_its_miss() -> None:
    """A touchdown one row late moves the ZMP's jump to the new foot by a row: the raw miss,
    the jump on one row, is charged through the moving mean of w rows as jump / w on w
    rows, an RMS sqrt(w) times smaller (the scale being the smoothed recording's)."""
    n, jump = 400, 0.05
    rec = _signals(n)
    t = rec.time_s
    zmp = np.column_stack([0.1 * t, np.where(t < 2.0, -jump / 2, jump / 2)])
    recorded = RecordedSignals(t, rec.joint_names, rec.q_cmd_rad, rec.q_meas_rad, zmp,
                               rec.trunk_tilt_rad)  # fmt: skip
    late_zmp = zmp.copy()
    late_zmp[200, 1] = -jump / 2  # the jump a row later
    late = RecordedSignals(t, rec.joint_names, rec.q_cmd_rad, rec.q_meas_rad, late_zmp,
                           rec.trunk_tilt_rad)  # fmt: skip
    width = round(ZMP_SMOOTHING_S / 0.01)
    smoothed = uniform_filter1d(zmp, width, axis=0, mode="nearest")
    detrended = [smoothed[:, k] - np.polyval(np.polyfit(t, smoothed[:, k], 1), t) for k in (0, 1)]
    scale = np.hypot(*(np.sqrt(np.mean(np.square(x))) for x in detrended))
    expected = jump / np.sqrt(width * n) / scale  # w rows of jump / w, RMS over n rows
    assert experiment_cost(recorded, late, models_loads=True).zmp == pytest.approx(expected)
    raw = jump / np.sqrt(n) / scale  # what the unsmoothed term charged
    assert experiment_cost(recorded, late, models_loads=True).zmp * np.sqrt(width) == (
        pytest.approx(raw)
    )


def _with_forces(rec: RecordedSignals, force: np.ndarray) -> RecordedSignals:
    return RecordedSignals(
        rec.time_s, rec.joint_names, rec.q_cmd_rad, rec.q_meas_rad, rec.zmp_m,
        rec.trunk_tilt_rad, force,
    )  # fmt: skip


def test_the_feet_forces_cost_against_the_weight_only_when_the_loads_are_modelled() -> None:
    """A lifted foot reads its sensor's offset: a 2 N offset on one foot of a robot whose
    sensors read 50 N in all costs e_f = 2/50, whatever the walk's load transfer."""
    rec = _signals(400)
    t = rec.time_s
    right = 25.0 + 25.0 * np.sign(np.cos(2 * np.pi * t))  # whole load steps, foot to foot
    recorded = _with_forces(rec, np.column_stack([right, 50.0 - right]))
    offset = _with_forces(rec, np.column_stack([right + 2.0, 50.0 - right]))
    assert experiment_cost(recorded, offset).force == 0.0  # not charged: loads not fitted
    terms = experiment_cost(recorded, offset, models_loads=True)
    assert terms.force == pytest.approx(2.0 / 50.0, rel=1e-9)
    assert terms.total(CostWeights()) == pytest.approx(terms.force**2 + terms.spectrum**2)
    assert terms.total(CostWeights(force=0.0)) == pytest.approx(terms.spectrum**2)
    # a touchdown one row late moves a 50 N step by a row; through the moving mean of w
    # rows it misses by 50/w N on w rows: RMS sqrt(w) times smaller than the raw miss
    late = _with_forces(rec, np.vstack([recorded.force_z_n[:1], recorded.force_z_n[:-1]]))
    raw_rms = np.sqrt(np.mean(np.sum(np.square(late.force_z_n - recorded.force_z_n), 1)))
    width = round(FORCE_SMOOTHING_S / 0.01)
    smoothed = experiment_cost(recorded, late, models_loads=True).force * 50.0
    assert smoothed == pytest.approx(raw_rms / np.sqrt(width), rel=0.05)
    # a source without forces (NaN) is not charged for them
    assert experiment_cost(rec, offset, models_loads=True).force == 0.0


def test_the_zmp_mean_is_kept_when_offsets_or_mass_are_fitted() -> None:
    doc: dict = {}
    for effects, kept in (("M,G", False), ("S", True), ("C", True), ("M,C", True)):
        problem = FitProblem(NAO, "M,G,S", default_parameters(NAO, effects), doc, ())
        assert problem.models_loads is kept
        # a fit whose cost charges the forces does not resume one from before them
        assert ("force_smoothing_s" in fingerprint(problem, CmaOptions(1))) is kept


def test_a_fallen_rollout_costs_more_the_earlier_it_falls() -> None:
    rec = _signals(400)
    early = experiment_cost(rec, _signals(100)).total(CostWeights())
    late = experiment_cost(rec, _signals(300)).total(CostWeights())
    assert early == pytest.approx(FAILED_COST * 1.75)
    assert late == pytest.approx(FAILED_COST * 1.25)


def test_config_errors_say_what_is_valid() -> None:
    with pytest.raises(ParameterError, match="robot must be one of nao, op3, teo; got 'asimo'"):
        IdentifySimConfig(data=("x",), robot="asimo")
    with pytest.raises(ParameterError, match="give at least one DATA folder"):
        IdentifySimConfig()
    with pytest.raises(ParameterError, match="--self-test records its own experiments"):
        IdentifySimConfig(data=("x",), self_test=True)
    with pytest.raises(ParameterError, match="--address is for --backend ray"):
        IdentifySimConfig(data=("x",), address="10.0.0.1:6379")
    with pytest.raises(
        ParameterError, match="backend must be one of local, pool, serial, ray, warp"
    ):
        IdentifySimConfig(data=("x",), backend="dask")
    with pytest.raises(ParameterError, match="generations must be an integer >= 1; got 0"):
        IdentifySimConfig(data=("x",), generations=0)
    with pytest.raises(ParameterError, match=r"restarts must lie in \[0, 9\]; got True"):
        IdentifySimConfig(data=("x",), restarts=True)
    with pytest.raises(ParameterError, match=r"restarts must lie in \[0, 2\]"):
        IdentifySimConfig(data=("x",), popsize=16_384, restarts=3)  # 131,072 > 65,536


def test_quick_nao_fits_pid_gain_scale_and_gear_stiffness() -> None:
    config = IdentifySimConfig(self_test=True, quick=True, effects="m, g")
    assert [p.name for p in config.fit_parameters()] == ["pid_gain_scale", "gear_stiffness"]
    assert config.effects == "M,G"
    assert config.sim_effects == "M,G,S"
    assert config.n_generations == 30


def test_ray_backend_without_ray_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    from zmpkit.simfit.backends import make_evaluator

    monkeypatch.setitem(sys.modules, "ray", None)  # as if not installed: import raises
    with pytest.raises(ParameterError, match=r"pip install zmpkit\[ray\]"):
        make_evaluator(None, "ray", address="auto")  # type: ignore[arg-type]


def test_warp_backend_without_mujoco_warp_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    from zmpkit.simfit.backends import make_evaluator

    monkeypatch.setitem(sys.modules, "mujoco_warp", None)  # as if not installed
    with pytest.raises(ParameterError, match=r"pip install 'zmpkit\[gpu\]'"):
        make_evaluator(None, "warp")  # type: ignore[arg-type]


def test_data_folder_errors_name_the_file(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="expected an experiment folder"):
        read_experiments([tmp_path / "missing"], NAO)
    with pytest.raises(InputFileError, match="no experiment folders given"):
        read_experiments([], NAO)
    with pytest.raises(InputFileError, match=r"summary\.json: cannot read the walk summary"):
        read_experiments([tmp_path], NAO)
    with pytest.raises(InputFileError, match=r"meta\.json"):
        read_experiments([tmp_path], TEO)


@pytest.mark.slow
def test_walk_folder_errors(nao_walk_folder: Path, tmp_path: Path) -> None:
    folder = tmp_path / "walk"
    shutil.copytree(nao_walk_folder, folder)
    series = folder / "timeseries.csv"
    lines = series.read_text().splitlines()
    cells = lines[2].split(",")
    cells[1] = "abc"
    series.write_text("\n".join([*lines[:2], ",".join(cells), *lines[3:]]) + "\n")
    with pytest.raises(InputFileError, match=r"timeseries.csv, line 3: expected numbers"):
        read_experiments([folder], NAO)
    cells[1] = str(float(lines[2].split(",")[1]) + 0.01)
    series.write_text("\n".join([*lines[:2], ",".join(cells), *lines[3:]]) + "\n")
    with pytest.raises(InputFileError, match=r"differs from the recorded command by 0\.01 rad"):
        read_experiments([folder], NAO)
    series.write_text("\n".join(lines) + "\n")
    summary = json.loads((folder / "summary.json").read_text())
    summary["fell"], summary["fall_time_s"] = True, 4.830999999999948
    (folder / "summary.json").write_text(json.dumps(summary))
    (fallen,) = read_experiments([folder], NAO)  # fitted up to the fall, less the margin
    assert fallen.fall_time_s == pytest.approx(4.831)
    assert fallen.signals.time_s[-1] <= float(lines[-1].split(",")[0]) - FALL_MARGIN_S + 1e-9


def test_resume_refuses_another_fit(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match=r"checkpoint\.json: no checkpoint here"):
        load_checkpoint(tmp_path)
    with pytest.raises(ParameterError, match="seed: 1 there, 2 now"):
        check_fingerprint({"seed": 1, "robot": "nao"}, {"seed": 2, "robot": "nao"}, tmp_path)


@pytest.fixture(scope="module")
def nao_walk_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from helpers.simfit_data import record_walk

    return record_walk(tmp_path_factory.mktemp("simfit_walk"))


@pytest.mark.slow
def test_walk_folder_reads_back_as_recorded(nao_walk_folder: Path) -> None:
    (experiment,) = read_experiments([nao_walk_folder], NAO)
    assert experiment.speed_mps == 0.2
    assert experiment.step_duration_s == 0.5
    assert experiment.duration_s == pytest.approx(1.5)
    signals = experiment.signals
    assert signals.q_meas_rad.shape == (signals.time_s.size, 6)
    assert signals.dt_s == pytest.approx(0.01)
    assert np.isfinite(signals.zmp_m).all(axis=1).mean() > 0.9


def test_identify_sim_refuses_to_resume_another_fit_in_one_line(
    nao_walk_folder: Path, tmp_path: Path
) -> None:
    """A checkpoint of the same data, robot and parameters but seed 1, resumed with seed 2."""
    from helpers.checkpoints import SphereEvaluator
    from helpers.fuzz import run_cli
    from zmpkit.simfit.optimizer import run_cma
    from zmpkit.simfit.truth_doc import base_truth_path as truth_path

    config = IdentifySimConfig(data=(str(nao_walk_folder),), quick=True, generations=2)
    params = config.fit_parameters()
    experiments = tuple(read_experiments(config.data, config.robot))
    problem = FitProblem(config.robot, config.sim_effects, params,
                         load_truth_doc(truth_path(config.robot, None)), experiments)  # fmt: skip
    run_cma(problem, SphereEvaluator(), CmaOptions(2, seed=1), tmp_path / "fit")
    argv = ["identify", "sim", str(nao_walk_folder), "--quick", "--generations", "2"]
    argv += ["--seed", "2", "--resume", str(tmp_path / "fit"), "--out", str(tmp_path / "out")]
    outcome = run_cli(argv)
    assert outcome.code == 2
    (line,) = outcome.stderr.strip().splitlines()
    assert line.endswith("it is another fit (seed: 1 there, 2 now)")


def test_identify_sim_command_bad_data_is_one_line_exit_2(tmp_path, capsys) -> None:
    from zmpkit.cli import main

    code = main(["identify", "sim", str(tmp_path / "missing"), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert "missing" in err


def test_a_repeated_teo_self_test_recording_finds_its_datasets(tmp_path: Path) -> None:
    """The hidden truth's temporary path is named after its content, so the step datasets'
    settings match on a second run (a resumed fit records nothing twice)."""
    from zmpkit.simfit.self_test import SelfTestPlan, record_experiments

    params = default_parameters(TEO, "G", ("gear_stiffness",))
    doc = load_truth_doc(base_truth_path(TEO, None))
    plan = SelfTestPlan((0.02,), (0.03,), hold_s=0.5, held_out_hold_s=0.5)
    first = record_experiments(TEO, plan, doc, params, np.array([45000.0]), "G", 1, tmp_path)
    (trial,) = first[0][0].glob("trial_*.csv")
    stamp = trial.stat().st_mtime_ns
    again = record_experiments(TEO, plan, doc, params, np.array([45000.0]), "G", 1, tmp_path)
    assert again == first
    assert trial.stat().st_mtime_ns == stamp  # resumed: the finished trial was kept


@pytest.mark.parametrize("controller", ["open", "zmpip"])
def test_a_walk_of_steps_that_do_not_divide_the_probe_is_read_back(
    controller: str, tmp_path: Path
) -> None:
    """A pattern walks round(duration / T) steps: with 0.4 s steps the standing phases'
    overhead must be measured on whole steps, or a 1.2 s walk reads as 1.4 s and is refused
    ("859 rows, but the re-planned walk has 899 frames" on a 6 s walk)."""
    from zmpkit.experiments.walk import run_walk_trial
    from zmpkit.experiments.walk_config import WalkConfig
    from zmpkit.experiments.walk_dataset import write_walk_folder

    config = WalkConfig(
        robot=NAO, speed_mps=0.15, step_duration_s=0.4, duration_s=1.2, effects="S", seed=1,
        figures=False, controller=controller,
    )  # fmt: skip
    trial = run_walk_trial(config)
    assert not trial.summary.fell
    folder = write_walk_folder(tmp_path / "walk", trial.summary, trial.pattern, trial.record)
    (experiment,) = read_experiments([folder], NAO)
    assert experiment.step_duration_s == pytest.approx(0.4)
    assert experiment.duration_s == pytest.approx(1.2)
    assert experiment.signals.time_s.size == trial.record.time_s.size


@pytest.mark.parametrize("step_s", [0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 0.7])
def test_the_probe_is_whole_steps_and_the_overhead_does_not_depend_on_it(step_s: float) -> None:
    from zmpkit.simfit.walk_plan import _pattern_end, probe_duration_s

    probe = probe_duration_s(step_s)
    steps = probe / step_s
    assert steps == pytest.approx(round(steps))
    assert round(steps) >= 2
    overhead = _pattern_end(NAO, 0.15, step_s, probe) - probe
    for n in (3, 7):
        assert _pattern_end(NAO, 0.15, step_s, n * step_s) - n * step_s == pytest.approx(overhead)
