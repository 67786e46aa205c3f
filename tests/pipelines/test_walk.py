"""The walk pipeline: rigid NAO walks, summary contract, metrics against closed forms."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_dataset import SERIES_COLUMNS
from zmpkit.pipelines.walk import run_walk
from zmpkit.pipelines.walk_files import write_walk
from zmpkit.robots.registry import get_robot
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.signals.contact_phases import foot_slip
from zmpkit.signals.spectra import amplitude_spectrum

CONTRACT = {
    "fell": bool,
    "mean_speed_mps": float,
    "commanded_speed_mps": float,
    "trunk_pitch_peak_hz": float,
    "trunk_pitch_peak_amplitude_rad": float,
    "trunk_pitch_std_rad": float,
    "mean_double_support_foot_distance_m": float,
    "foot_slip_m": float,
}


@pytest.fixture(scope="module")
def rigid_walk(tmp_path_factory):
    out = tmp_path_factory.mktemp("walk")
    calls = []
    result = write_walk(
        run_walk(
            WalkConfig(get_robot("nao"), duration_s=3.0, effects="none"),
            lambda t, T: calls.append((t, T)),
        ),
        out,
    )
    return out, result, calls


@pytest.mark.slow
def test_rigid_nao_walks_three_seconds_without_falling(rigid_walk) -> None:
    _, result, calls = rigid_walk
    assert not result.summary.fell
    assert result.summary.mean_speed_mps == pytest.approx(0.2, abs=0.02)
    assert calls
    assert calls[-1][0] <= calls[-1][1]


@pytest.mark.slow
def test_summary_json_keeps_its_contract(rigid_walk) -> None:
    out, _, _ = rigid_walk
    summary = json.loads((out / "summary.json").read_text())
    for key, kind in CONTRACT.items():
        assert isinstance(summary[key], kind), key
    assert summary["commanded_speed_mps"] == 0.2


def test_series_and_figures_are_written(rigid_walk) -> None:
    out, result, _ = rigid_walk
    with (out / "timeseries.csv").open() as f:
        rows = list(csv.reader(f))
    assert tuple(rows[0]) == SERIES_COLUMNS
    assert len(rows) - 1 == result.record.time_s.size
    for name in ("trunk_pitch.png", "trunk_pitch_spectrum.png", "feet_in_contact.png",
                 "feet_distance.png", "joint_RAnklePitch.png", "joint_RKneePitch.png",
                 "joint_RHipPitch.png"):  # fmt: skip
        assert (out / name).stat().st_size > 0


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [("robot", "teo", "robot 'teo' has no walking defaults"),
     ("effects", "X", "unknown effect 'X'"),
     ("seed", -1, "seed must be an integer >= 0"),
     ("duration_s", 0.0, r"duration_s must lie in \[0.5, 3600.0\] s, got 0.0 s"),
     ("speed_mps", -1.0, r"speed_mps \(forward\) must lie in \[0.0, 0.48\] m/s, got -1.0 m/s"),
     ("step_duration_s", 0.05, r"step_duration_s must lie in \[0.2, 2.0\] s")],
)  # fmt: skip
def test_bad_config_is_named(field: str, value: object, match: str) -> None:
    if field == "robot":
        value = get_robot(str(value))
    with pytest.raises(ParameterError, match=match):
        WalkConfig(**{"robot": get_robot("nao"), field: value})


def test_spectrum_recovers_a_sinusoid() -> None:
    t = np.arange(800) * 0.01
    spectrum = amplitude_spectrum(0.03 * np.sin(2 * np.pi * 2.0 * t) + 0.1 * t, 0.01)
    peak_hz, amplitude = spectrum.peak()
    assert peak_hz == pytest.approx(2.0)
    assert amplitude == pytest.approx(0.03, rel=0.01)


def test_measured_zmp_of_a_point_load() -> None:
    # 40 N down at (0.03, -0.01) on the floor, sensor 5 mm above the floor at (0.01, 0.0).
    sensor = np.array([[[0.01, 0.0, 0.005], [0.0, 0.0, 0.005]]])
    load, force = np.array([0.03, -0.01, 0.0]), np.array([0.0, 0.0, 40.0])
    moment = np.cross(load - sensor[0, 0], force)
    forces = np.array([[force, [0.0, 0.0, 0.0]]])
    moments = np.array([[moment, [0.0, 0.0, 0.0]]])
    assert zmp_in_world(forces, moments, sensor)[0] == pytest.approx([0.03, -0.01])
    assert np.all(np.isnan(zmp_in_world(forces * 0, moments * 0, sensor)))


def test_foot_slip_measures_displacement_in_stance() -> None:
    n = 20
    sole = np.zeros((n, 1, 3))
    sole[:, 0, 0] = np.linspace(0.0, -0.004, n)
    slip = foot_slip(sole, np.ones((n, 1), bool), np.ones(n, bool))
    assert slip.mean_x_m == pytest.approx(-0.004)
    assert slip.mean_abs_m == pytest.approx(0.004)


@pytest.mark.slow
def test_walk_command_writes_the_summary_contract(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from zmpkit.cli import main

    out = tmp_path / "walk"
    args = ["walk", "--effects", "none", "--duration", "3", "--out", str(out)]
    assert main(args) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["fell"] is False
    assert summary["commanded_speed_mps"] == pytest.approx(0.2)
    assert "fell: False" in capsys.readouterr().out
    # a 3 s walk's steady window is shorter than two gait cycles: no path speed, said why
    assert summary["path_speed_mps"] is None


@pytest.mark.slow
def test_a_turning_walk_reports_its_speed_along_the_path(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The forward speed of a turning walk is its chord along x; the path speed is what it
    walks (measured: 0.071 and 0.152 m/s at 0.15 m/s and 0.2 rad/s, every effect on)."""
    from zmpkit.cli import main

    out = tmp_path / "turn"
    args = ["walk", "--speed", "0.15", "--turn-rate", "0.2", "--duration", "10"]
    assert main([*args, "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["fell"] is False
    assert summary["path_speed_mps"] == pytest.approx(0.15, rel=0.05)
    assert summary["mean_speed_mps"] < 0.6 * 0.15  # the chord along x
    assert "along the path 0.15" in capsys.readouterr().out
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "speed along the path" in html


def test_walk_command_bad_input_is_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from zmpkit.cli import main

    assert main(["walk", "--effects", "Q", "--out", str(tmp_path)]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert main(["walk"]) == 2
    assert "walking needs --out DIR" in capsys.readouterr().err


@pytest.mark.slow
def test_walk_command_too_short_for_a_speed_says_undefined(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from zmpkit.cli import main

    assert main(["walk", "--effects", "none", "--duration", "2", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["mean_speed_mps"] is None  # 2 s leave no steady walk to fit a speed on
    assert "speed undefined m/s" in out


@pytest.mark.slow
def test_a_window_a_sample_short_of_two_gait_cycles_leaves_the_path_speed_unmeasured() -> None:
    """4 s of 0.6 s steps leave a steady window of 2.4 s, sampled as 2.39 s: the path speed
    (which needs two 1.2 s cycles) is not measured, the walk still is (it stopped with
    'need a window of at least two periods' before)."""
    config = WalkConfig(
        robot=get_robot("nao"), speed_mps=0.15, step_duration_s=0.6, duration_s=4.0,
        effects="none", figures=False,
    )  # fmt: skip
    summary = run_walk(config).summary
    assert summary.path_speed_mps is None
    assert summary.mean_speed_mps == pytest.approx(0.15, rel=0.1)
