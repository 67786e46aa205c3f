"""A real robot's recorded steps through a step manifest: logs in, identified model out."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from helpers.ft_data import FEET_YAML, wrench_in_sensor, write_log
from zmpkit.cli import main
from zmpkit.errors import InputFileError
from zmpkit.identify import BalanceParams
from zmpkit.io import FT_LOG_COLUMNS, read_feet_yaml
from zmpkit.io.step_manifest import read_step_manifest

A, B, C = 0.834, 1.024, -0.0004  # paper A eq. 13: the robot's steady-state error model
TARGETS_M = (0.0, 0.02, 0.04, 0.06, 0.08, 0.10)
T_STEP_S, RATE_HZ, WEIGHT_N = 2.0, 200.0, 307.0


def _rows(feet: dict, target: float, seed: int) -> np.ndarray:
    """Both feet's sensor wrenches of a 2nd-order ZMP step to f(target) at T_STEP_S."""
    t = np.arange(0.0, 8.0, 1.0 / RATE_HZ)
    zeta, omega = 0.3, 6.0
    tau = np.clip(t - T_STEP_S, 0.0, None)
    wd = omega * math.sqrt(1 - zeta**2)
    shape = 1 - np.exp(-zeta * omega * tau) * (
        np.cos(wd * tau) + zeta / math.sqrt(1 - zeta**2) * np.sin(wd * tau)
    )
    final = A * target**2 + B * target + C if target else C
    zmp_x = C + (final - C) * shape + np.random.default_rng(seed).normal(0.0, 5e-5, t.size)
    rows = []
    for k, x in enumerate(zmp_x):
        row = [t[k]]
        for side in ("right", "left"):
            m = feet[side]
            point = np.array([x, m.position[1], m.ground_height])
            row += list(wrench_in_sensor(point, np.array([0, 0, WEIGHT_N]), m.position, m.rotation))
        rows.append(row)
    return np.array(rows)


@pytest.fixture
def manifest(tmp_path: Path) -> Path:
    (tmp_path / "feet.yaml").write_text(FEET_YAML)
    feet = read_feet_yaml(tmp_path / "feet.yaml")
    trials = []
    for k, target in enumerate(TARGETS_M):
        rows = _rows(feet, target, seed=k)
        if k == 3:  # one log as Parquet, the rest CSV
            table = pa.table({name: rows[:, i] for i, name in enumerate(FT_LOG_COLUMNS)})
            pq.write_table(table, tmp_path / f"step_{k}.parquet")
            name = f"step_{k}.parquet"
        else:
            write_log(tmp_path / f"step_{k}.csv", rows)
            name = f"step_{k}.csv"
        trials.append(f"  - {{log: {name}, target_m: {target}, t_step_s: {T_STEP_S}}}")
    path = tmp_path / "steps.yaml"
    path.write_text(
        "plane: sagittal\nfeet: feet.yaml\nmass_kg: 62.6\nlength_m: 0.777\n"
        "startup_window_s: 0.5\ntrials:\n" + "\n".join(trials) + "\n"
    )
    return path


@pytest.mark.slow
def test_manifest_trials_measure_the_recorded_zmp(manifest: Path) -> None:
    steps = read_step_manifest(manifest)
    assert [t.zmp_ref for t in steps.trials] == list(TARGETS_M)
    last = steps.trials[-1]
    settled = last.zmp_measured[last.time > 4.0].mean()
    # the start-up offset (C at rest) is removed, as TEO's code does
    assert settled == pytest.approx(A * 0.1**2 + B * 0.1, abs=2e-5)


@pytest.mark.slow
def test_identify_balance_from_recorded_logs(manifest: Path, tmp_path: Path) -> None:
    assert main(["identify", "balance", str(manifest), "--out", str(tmp_path / "out")]) == 0
    params = BalanceParams.from_yaml(tmp_path / "out" / "params.yaml")
    model = params.plane("sagittal").error_model
    assert model.kind == "quadratic"
    a, b, _ = model.coefficients
    assert a == pytest.approx(A, rel=0.05)
    assert b == pytest.approx(B, rel=0.005)
    assert params.com_height == pytest.approx(0.777)


@pytest.mark.slow
def test_manifest_errors_name_the_field(manifest: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(manifest.read_text().replace("t_step_s: 2.0", "t_step: 2.0", 1))
    with pytest.raises(InputFileError, match=r"trials\[0\] has unknown field 't_step'"):
        read_step_manifest(bad)
    bad.write_text(manifest.read_text().replace("length_m: 0.777\n", ""))
    with pytest.raises(InputFileError, match=r"missing field 'length_m'"):
        read_step_manifest(bad)


def test_a_light_robots_threshold_counts_a_lightly_loaded_foot(tmp_path: Path) -> None:
    """A 3 kg robot stands on both feet (15 N each, centres of pressure at 10 mm), then leans
    onto its right foot: 25 N at 30 mm, the left 5 N at −10 mm. With the 10 N default the
    left foot drops out of contact and the ZMP jumps to the right foot's 30 mm; with the
    robot's own threshold (5 % of its weight, 1.5 N) it is the F_z-weighted mean of both
    (eq. 6): 23.3 mm. The manifest's ``contact_threshold_n`` is the one its trials use."""
    (tmp_path / "feet.yaml").write_text(FEET_YAML)
    feet = read_feet_yaml(tmp_path / "feet.yaml")
    rows = []
    for t in np.arange(0.0, 4.0, 1.0 / RATE_HZ):
        before = t <= 1.0  # the start-up window [0.5, 1.0] s is all before
        row = [t]
        for side in ("right", "left"):
            m = feet[side]
            load_n = 15.0 if before else (25.0 if side == "right" else 5.0)
            x = 0.01 if before else (0.03 if side == "right" else -0.01)
            point = np.array([x, m.position[1], m.ground_height])
            row += list(wrench_in_sensor(point, np.array([0.0, 0.0, load_n]), m.position,
                                         m.rotation))  # fmt: skip
        rows.append(row)
    write_log(tmp_path / "lean.csv", np.array(rows))
    head = "plane: sagittal\nfeet: feet.yaml\nmass_kg: 3.0\nlength_m: 0.2\nstartup_window_s: 0.5\n"
    trial = "trials:\n  - {log: lean.csv, target_m: 0.02, t_step_s: 1.0}\n"
    default, own = tmp_path / "default.yaml", tmp_path / "own.yaml"
    default.write_text(head + trial)
    own.write_text(head + "contact_threshold_n: 1.5\n" + trial)
    step = {}
    for name, path in (("default", default), ("own", own)):
        steps = read_step_manifest(path).trials[0]
        step[name] = float(steps.zmp_measured[steps.time > 0.5].mean())  # offset removed
    assert step["default"] == pytest.approx(0.03 - 0.01, abs=1e-9)
    assert step["own"] == pytest.approx((25.0 * 0.03 + 5.0 * -0.01) / 30.0 - 0.01, abs=1e-9)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("0", r"contact_threshold_n must lie in"),
        ("abc", r"field 'contact_threshold_n' must be a number"),
    ],
)
@pytest.mark.slow
def test_a_bad_manifest_threshold_is_one_line(
    manifest: Path, tmp_path: Path, value: str, message: str
) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(f"contact_threshold_n: {value}\n" + manifest.read_text())
    with pytest.raises(InputFileError, match=message) as caught:
        read_step_manifest(bad)
    assert len(str(caught.value).splitlines()) == 1
