"""Balance validation outcomes and Table 1 on synthetic step trials with known answers."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from zmpkit.analysis.balance_validation import evaluate_trial, percent_error
from zmpkit.analysis.table1 import TABLE1_COLUMNS, Table1Row, table1_markdown, write_table1_csv
from zmpkit.signals import StepTrial

ZETA, OMEGA_N = 0.3, 6.0  # [-], [rad/s]


def _trial(target: float, final: float, seed: int = 0) -> StepTrial:
    """A 2nd-order ZMP step to ``final`` [m] at t = 1 s, 1 kHz, with 20 µm noise."""
    t = np.arange(0.0, 8.0, 0.001)
    tau = np.clip(t - 1.0, 0.0, None)
    wd = OMEGA_N * math.sqrt(1 - ZETA**2)
    env = np.exp(-ZETA * OMEGA_N * tau)
    shape = 1 - env * (np.cos(wd * tau) + ZETA / math.sqrt(1 - ZETA**2) * np.sin(wd * tau))
    noise = np.random.default_rng(seed).normal(0.0, 2e-5, t.size)
    return StepTrial(time=t, zmp_measured=final * shape + noise, zmp_ref=target, t_step=1.0)


def test_outcome_matches_second_order_closed_form() -> None:
    outcome = evaluate_trial("lipm", _trial(0.10, 0.1116))
    assert outcome.zmp_measured == pytest.approx(0.1116, abs=2e-5)
    assert outcome.error_pct == pytest.approx(11.6, abs=0.03)
    overshoot = 100 * math.exp(-ZETA * math.pi / math.sqrt(1 - ZETA**2))  # 37.2 %
    assert outcome.overshoot_pct == pytest.approx(overshoot, abs=0.5)
    # 5 % band of a 2nd-order envelope: ≈ −ln(0.05·√(1−ζ²))/(ζ ω_n), within one period
    envelope_settle = -math.log(0.05 * math.sqrt(1 - ZETA**2)) / (ZETA * OMEGA_N)
    assert outcome.settling_time_s == pytest.approx(envelope_settle, abs=2 * math.pi / OMEGA_N)
    assert 0.0 < outcome.rms_oscillation_m < 0.1116


def test_zero_target_has_no_percent_error() -> None:
    assert percent_error(0.0004, 0.0) is None
    assert percent_error(None, 0.05) is None
    outcome = evaluate_trial("dlipm", _trial(0.0, 1e-6))
    assert outcome.error_pct is None
    assert outcome.overshoot_pct is None


def test_table1_csv_has_the_contract_columns(tmp_path: Path) -> None:
    rows = [
        Table1Row(
            "sagittal",
            x,
            evaluate_trial("lipm", _trial(x, 1.1 * x)),
            evaluate_trial("dlipm", _trial(x, x)),
            evaluate_trial("linear", _trial(x, 1.05 * x)),
            fitted_on=k % 2 == 0,
        )
        for k, x in enumerate((0.0, 0.05, 0.1))
    ]
    path = write_table1_csv(rows, tmp_path / "table1.csv")
    with path.open() as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames or ()) == TABLE1_COLUMNS
        got = list(reader)
    assert got[0]["lipm_error_pct"] == ""
    assert float(got[2]["lipm_error_pct"]) == pytest.approx(10.0, abs=0.05)
    assert float(got[2]["dlipm_error_pct"]) == pytest.approx(0.0, abs=0.05)
    assert "| sagittal | 0.05 * |" in table1_markdown(rows)
