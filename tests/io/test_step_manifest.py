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


def test_manifest_trials_measure_the_recorded_zmp(manifest: Path) -> None:
    steps = read_step_manifest(manifest)
    assert [t.zmp_ref for t in steps.trials] == list(TARGETS_M)
    last = steps.trials[-1]
    settled = last.zmp_measured[last.time > 4.0].mean()
    # the start-up offset (C at rest) is removed, as TEO's code does
    assert settled == pytest.approx(A * 0.1**2 + B * 0.1, abs=2e-5)


def test_identify_balance_from_recorded_logs(manifest: Path, tmp_path: Path) -> None:
    assert main(["identify", "balance", str(manifest), "--out", str(tmp_path / "out")]) == 0
    params = BalanceParams.from_yaml(tmp_path / "out" / "params.yaml")
    model = params.plane("sagittal").error_model
    assert model.kind == "quadratic"
    a, b, _ = model.coefficients
    assert a == pytest.approx(A, rel=0.05)
    assert b == pytest.approx(B, rel=0.005)
    assert params.com_height == pytest.approx(0.777)


def test_manifest_errors_name_the_field(manifest: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(manifest.read_text().replace("t_step_s: 2.0", "t_step: 2.0", 1))
    with pytest.raises(InputFileError, match=r"trials\[0\] has unknown field 't_step'"):
        read_step_manifest(bad)
    bad.write_text(manifest.read_text().replace("length_m: 0.777\n", ""))
    with pytest.raises(InputFileError, match=r"missing field 'length_m'"):
        read_step_manifest(bad)
