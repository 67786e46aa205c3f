"""Step / push experiments: lean geometry, trials, datasets, resume, analysis and the CLI."""

from __future__ import annotations

import csv
import json
import math
import pickle
from pathlib import Path

import numpy as np
import pytest

from zmpkit.cli import main
from zmpkit.errors import InputFileError, ParameterError, SimulationDivergedError
from zmpkit.experiments import (
    META_FILE,
    STEADY_STATE_COLUMNS,
    PushConfig,
    StepExperimentConfig,
    design_lean_model,
    parse_targets,
    read_step_dataset,
    run_step_sweep,
    step_responses,
    trial_file_name,
)
from zmpkit.experiments import sweep as sweep_module
from zmpkit.experiments.lean import design_support_interval, lean_angle
from zmpkit.pipelines.sim_push import run_sim_push
from zmpkit.pipelines.sim_push_files import write_sim_push
from zmpkit.robots.registry import get_robot

TEO = get_robot("teo")

FAST = {"settle_s": 1.0, "startup_window_s": 0.3, "hold_s": 1.0}
"""A short timeline for tests that need data, not a settled response [s]."""


def _config(**kw) -> StepExperimentConfig:
    return StepExperimentConfig(**{"robot": TEO, "effects": "none", **FAST, **kw})


def _files(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


# --- the lean --------------------------------------------------------------------------


def test_sagittal_lean_length_is_the_rigid_model_lever_about_the_ankle() -> None:
    lean = design_lean_model(TEO, "sagittal")
    # dx_com/dθ of the rigid model about the ankle axis, 0.123 m above the sole: ≈ 0.777 m,
    # well short of the 0.893 m CoM height measured from the ground (paper A §4.1).
    assert lean.lean_length_m == pytest.approx(0.7767, abs=0.002)
    assert lean.joint_targets(0.1) == {"right_ankle_frontal": -0.1, "left_ankle_frontal": -0.1}


def test_frontal_lean_closes_the_four_bar_and_keeps_the_feet_flat() -> None:
    lean = design_lean_model(TEO, "frontal")
    right, left, pelvis = lean.leg_tilts(0.15)
    assert (right + left) / 2 == pytest.approx(0.15, abs=1e-12)
    legs = lean.hips - lean.ankles
    hips = [
        lean.ankles[k]
        + np.array(
            [v[0] * math.cos(a) + v[1] * math.sin(a), -v[0] * math.sin(a) + v[1] * math.cos(a)]
        )
        for k, (v, a) in enumerate(zip(legs, (right, left), strict=True))
    ]
    width0 = np.linalg.norm(lean.hips[1] - lean.hips[0])
    assert np.linalg.norm(hips[1] - hips[0]) == pytest.approx(width0, abs=1e-12)
    q = lean.joint_targets(0.15)
    # foot flat: pelvis tilt + hip roll + ankle roll = 0 on each side (all axes +x)
    for side, tilt in (("right", right), ("left", left)):
        assert q[f"{side}_ankle_sagittal"] == pytest.approx(tilt)
        assert -q[f"{side}_hip_sagittal"] == pytest.approx(tilt - pelvis)
    assert 0.4 < lean.lean_length_m < 0.7


def test_target_out_of_reach_is_refused() -> None:
    with pytest.raises(ParameterError, match="out of reach"):
        lean_angle(0.9, 0.777)
    message = (
        r"^ZMP target 0.9 m lies outside teo's support polygon in the sagittal plane; "
        r"reachable targets lie in \(-0.07, 0.175\) m$"
    )
    with pytest.raises(ParameterError, match=message):
        run_step_sweep(_config(targets_m=(0.9,)), "/nonexistent/never/created")


def test_support_interval_is_teo_soles() -> None:
    # Soles 0.245 m long, the ankle 0.07 m from the heel; 0.140 m wide, ankles at y = ±0.1285 m.
    assert design_support_interval(TEO, "sagittal") == pytest.approx((-0.07, 0.175))
    assert design_support_interval(TEO, "frontal") == pytest.approx((-0.1985, 0.1985))


# --- config and parsing ----------------------------------------------------------------


def test_parse_targets_range_includes_stop_and_lists_work() -> None:
    assert parse_targets("0:0.10:0.01") == pytest.approx([0.01 * k for k in range(11)])
    assert parse_targets("0.02, 0.05") == (0.02, 0.05)
    with pytest.raises(ParameterError, match=r"--targets expects START:STOP:STEP"):
        parse_targets("0:0.1")


def test_trial_file_names() -> None:
    assert trial_file_name("sagittal", 0.03) == "trial_sagittal_0030.csv"
    assert trial_file_name("frontal", 0.0) == "trial_frontal_0000.csv"
    assert trial_file_name("sagittal", -0.0125) == "trial_sagittal_m0012p500.csv"


def test_zmpkit_errors_survive_a_process_pool() -> None:
    for error in (
        SimulationDivergedError(1.5, "joint 'knee'", "bad qacc"),
        InputFileError("f.csv", "bad", row=3),
    ):
        assert str(pickle.loads(pickle.dumps(error))) == str(error)


# --- datasets --------------------------------------------------------------------------


@pytest.mark.slow
def test_same_seed_gives_an_identical_dataset_serial_or_pooled(tmp_path: Path) -> None:
    config = _config(effects="S", targets_m=(0.0, 0.03), seed=5)
    run_step_sweep(config, tmp_path / "a", workers=1)
    run_step_sweep(config, tmp_path / "b", workers=2)
    run_step_sweep(_config(effects="S", targets_m=(0.0, 0.03), seed=6), tmp_path / "c", workers=1)
    a, b, c = (_files(tmp_path / n) for n in "abc")
    assert a == b
    assert a["trial_sagittal_0030.csv"] != c["trial_sagittal_0030.csv"]


def test_dataset_round_trip(tmp_path: Path) -> None:
    config = _config(targets_m=(0.02,), plane="frontal")
    data = run_step_sweep(config, tmp_path, workers=1)
    again = read_step_dataset(tmp_path)
    meta = json.loads((tmp_path / META_FILE).read_text())
    assert meta["robot"] == "teo"
    assert meta["effects"] == "none"
    assert meta["seed"] == 0
    assert meta["units"]["right_tz"] == "N*m"
    assert meta["units"]["imu_acc_z"] == "m/s^2"
    assert set(meta["sensor_mounts"]) == {"right", "left"}
    trial = again.trials[0]
    assert trial.target_m == 0.02
    assert trial.plane == "frontal"
    assert trial.t_step_s == pytest.approx(1.3)
    assert trial.right_wrench.shape == (len(trial.time), 6)
    assert trial.encoders.shape == trial.commanded.shape == (len(trial.time), 14)
    np.testing.assert_allclose(trial.left_wrench, data.trials[0].left_wrench, rtol=1e-12)
    header = (tmp_path / "trial_frontal_0020.csv").read_text().splitlines()[0].split(",")
    assert header[:13] == [
        "time",
        *(f"{s}_{a}" for s in ("right", "left") for a in ("fx", "fy", "fz", "tx", "ty", "tz")),
    ]
    # gravity: the sensors weigh the robot (rigid, perfect sensors) within 0.5 %
    fz = trial.right_wrench[:, 2] + trial.left_wrench[:, 2]
    assert fz[:10].mean() == pytest.approx(62.6 * 9.81, rel=0.005)


def test_reader_names_the_missing_field_and_column(tmp_path: Path) -> None:
    run_step_sweep(_config(targets_m=(0.01,)), tmp_path, workers=1)
    csv_path = tmp_path / "trial_sagittal_0010.csv"
    text = csv_path.read_text()
    csv_path.write_text(text.replace("enc_trunk_axial", "encoder_trunk_axial", 1))
    with pytest.raises(InputFileError, match=r"trial_sagittal_0010\.csv.*'enc_trunk_axial'"):
        read_step_dataset(tmp_path)
    meta = json.loads((tmp_path / META_FILE).read_text())
    del meta["sensor_mounts"]
    (tmp_path / META_FILE).write_text(json.dumps(meta))
    with pytest.raises(InputFileError, match=r"meta\.json: missing field 'sensor_mounts'"):
        read_step_dataset(tmp_path)


def test_resume_skips_finished_trials_and_refuses_other_settings(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    config = _config(targets_m=(0.0, 0.02, 0.04))
    run_step_sweep(config, tmp_path, workers=1)
    before = _files(tmp_path)
    (tmp_path / "trial_sagittal_0020.csv").unlink()
    ran: list[float] = []
    real = sweep_module.run_step_trial
    monkeypatch.setattr(
        sweep_module, "run_step_trial", lambda c, t, ctl=None: ran.append(t) or real(c, t, ctl)
    )
    seen: list[tuple[int, int]] = []
    run_step_sweep(config, tmp_path, workers=1, progress=lambda k, n, t: seen.append((k, n)))
    assert ran == [0.02]
    assert seen == [(1, 3), (2, 3), (3, 3)]
    assert _files(tmp_path) == before
    with pytest.raises(ParameterError, match="another 'settings'"):
        run_step_sweep(_config(targets_m=(0.0,), hold_s=2.0), tmp_path, workers=1)


# --- analysis --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("plane", "target"), [("sagittal", 0.02), ("sagittal", 0.08), ("frontal", 0.06)]
)
def test_effects_off_steady_state_error_is_below_half_a_percent(
    tmp_path: Path, plane: str, target: float
) -> None:
    config = _config(targets_m=(target,), plane=plane, hold_s=4.5)
    (response,) = step_responses(run_step_sweep(config, tmp_path, workers=1))
    assert abs(response.error_pct) < 0.5
    assert response.zmp_expected[-1] == pytest.approx(target, rel=1e-9)


def test_steady_state_csv_and_figure(tmp_path: Path) -> None:
    swept = run_sim_push(_config(targets_m=(0.0, 0.03), hold_s=2.0), tmp_path, workers=1)
    result = write_sim_push(swept, tmp_path)
    with result.files["steady_state"].open() as f:
        rows = list(csv.reader(f))
    assert tuple(rows[0]) == STEADY_STATE_COLUMNS
    assert rows[1][0] == "sagittal"
    assert float(rows[1][1]) == 0.0
    assert rows[1][3] == ""
    assert rows[1][4] == ""
    assert float(rows[2][1]) == 0.03
    assert rows[2][3] != ""
    assert result.files["figure"].stat().st_size > 10_000


def test_a_push_moves_the_zmp_and_it_comes_back(tmp_path: Path) -> None:
    push = PushConfig(force_n=60.0, duration_s=0.2)
    config = _config(targets_m=(0.0,), push=push, hold_s=3.0)
    (response,) = step_responses(run_step_sweep(config, tmp_path, workers=1))
    during = response.zmp_measured[
        (response.time_since_step > 0) & (response.time_since_step < 0.6)
    ]
    assert np.max(np.abs(during)) > 0.005
    assert abs(response.steady_state) < 0.002


# --- the command -----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["--targets", "0:x"], "--targets expects START:STOP:STEP"),
        (["--targets", "0.1:0:0.01"], "--targets expects START:STOP:STEP"),
        (["--plane", "coronal"], "--plane expects one of sagittal, frontal; got 'coronal'"),
        (["--effects", "M,X"], "--effects expects all, none or comma-separated letters"),
        (["--push-force", "50"], "--push-force N and --push-duration S go together"),
    ],
)
def test_bad_options_exit_2_with_one_line(
    tmp_path: Path, args: list[str], expected: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["sim", "push", "--out", str(tmp_path / "o"), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert err.startswith("zmpkit: error: ")
    assert expected in err
    assert not (tmp_path / "o").exists()


def test_sim_push_help(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sim", "push", "--help"]) == 0
    out = capsys.readouterr().out
    assert "Usage: zmpkit sim push" in out
    assert "--push-duration" in out


@pytest.mark.slow
def test_sim_push_end_to_end(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    args = ["sim", "push", "--targets", "0,0.02", "--effects", "none", "--hold", "1.5"]
    assert main([*args, "--seed", "3", "--out", str(out), "--workers", "1"]) == 0
    assert {"meta.json", "steady_state.csv", "steps.png", "trial_sagittal_0020.csv"} <= {
        p.name for p in out.iterdir()
    }
    assert "2 trials" in capsys.readouterr().out
