"""Balance validation outcomes and Table 1 on synthetic step trials with known answers."""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest

from zmpkit.analysis.balance_validation import evaluate_trial, percent_error
from zmpkit.analysis.balance_verdict import plane_verdict
from zmpkit.analysis.table1 import (
    ABSOLUTE_COLUMNS,
    BASE_COLUMNS,
    FEEDBACK_COLUMNS,
    STATUS_COLUMNS,
    TABLE1_COLUMNS,
    Table1Row,
    table1_markdown,
    unsettled_lines,
    write_table1_csv,
)
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


def test_a_small_step_has_its_error_in_mm_and_no_overshoot_from_noise() -> None:
    """A 3 mm target the robot barely moves to (0.05 mm, under 5 σ of 20 µm noise): the
    overshoot of such a step is noise over noise (it read thousands of percent); the error
    is stated in mm beside the percentage."""
    small = evaluate_trial("lipm", _trial(0.003, 0.00005))
    assert small.overshoot_pct is None
    assert small.settling_time_s is None
    assert small.error_mm == pytest.approx(0.05 - 3.0, abs=0.02)
    assert small.error_pct == pytest.approx(100 * (0.00005 - 0.003) / 0.003, abs=1.0)
    clear = evaluate_trial("lipm", _trial(0.003, 0.0031))  # 3.1 mm ≫ 5 σ: measured
    assert clear.overshoot_pct == pytest.approx(37.2, abs=2.0)
    assert clear.error_mm == pytest.approx(0.1, abs=0.02)


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


# --- creep, extrapolation and the verdict -------------------------------------------------------

ORIGINAL_COLUMNS = (
    "plane", "zmp_ref", "lipm_zmp", "lipm_error_pct", "dlipm_zmp", "dlipm_error_pct",
    "lipm_overshoot_pct", "dlipm_overshoot_pct", "lipm_settling_s", "dlipm_settling_s",
    "linear_zmp", "linear_error_pct", "linear_overshoot_pct", "linear_settling_s",
    "lipm_rms_oscillation_m", "dlipm_rms_oscillation_m", "fitted_on",
)  # fmt: skip


def _creeping(target: float, final: float, rate_m_s: float) -> StepTrial:
    """:func:`_trial` with a creep of ``rate_m_s`` [m/s] after the step."""
    trial = _trial(target, final)
    creep = rate_m_s * np.clip(trial.time - 1.0, 0.0, None)
    return StepTrial(trial.time, trial.zmp_measured + creep, target, 1.0)


def _rows(dlipm_far: float, lipm_far_rate: float = 0.0, fit_high: float = 0.1) -> list[Table1Row]:
    rows = []
    for k, x in enumerate((0.0, 0.05, 0.1)):
        lipm = _creeping(x, 1.1 * x, lipm_far_rate if x == 0.1 else 0.0)
        dlipm = _trial(x, dlipm_far * x if x == 0.1 else 1.01 * x)
        rows.append(
            Table1Row(
                "frontal",
                x,
                evaluate_trial("lipm", lipm),
                evaluate_trial("dlipm", dlipm),
                evaluate_trial("linear", _trial(x, 1.02 * x)),
                fitted_on=k % 2 == 0,
                fit_range_m=(0.0, fit_high),
            )
        )
    return rows


def test_earlier_columns_are_kept_and_the_new_ones_follow() -> None:
    assert BASE_COLUMNS == ORIGINAL_COLUMNS
    assert TABLE1_COLUMNS[: len(ORIGINAL_COLUMNS)] == ORIGINAL_COLUMNS
    status_end = len(ORIGINAL_COLUMNS) + len(STATUS_COLUMNS)
    assert TABLE1_COLUMNS[len(ORIGINAL_COLUMNS) : status_end] == STATUS_COLUMNS
    feedback_end = status_end + len(FEEDBACK_COLUMNS)
    assert TABLE1_COLUMNS[status_end:feedback_end] == FEEDBACK_COLUMNS
    assert TABLE1_COLUMNS[feedback_end:] == ABSOLUTE_COLUMNS == (
        "lipm_error_mm", "dlipm_error_mm", "linear_error_mm", "lipm_pid_error_mm",
        "dlipm_fb_error_mm",
    )  # fmt: skip
    assert "lipm_drift_mm_s" in STATUS_COLUMNS
    assert STATUS_COLUMNS[-1] == "extrapolated"
    assert FEEDBACK_COLUMNS[:4] == (
        "lipm_pid_zmp",
        "lipm_pid_error_pct",
        "lipm_pid_overshoot_pct",
        "lipm_pid_settling_s",
    )
    assert "dlipm_fb_settling_s" in FEEDBACK_COLUMNS
    assert "dlipm_fb_status" in FEEDBACK_COLUMNS


def test_a_creeping_trial_reports_its_drift_instead_of_an_error(tmp_path: Path) -> None:
    rows = _rows(1.0, lipm_far_rate=2e-4)  # 0.2 mm/s: 2 mm in the 10 s creep horizon
    far = rows[-1].lipm
    assert far.error_pct is None
    assert far.status == "drifting"
    assert far.drift_mm_s == pytest.approx(0.2, rel=0.2)
    assert far.end_error_pct == pytest.approx(10.0 + 100 * 2e-4 * 6.5 / 0.1, abs=0.3)
    cells = rows[-1].cells()
    assert cells["lipm_error_pct"] == ""
    assert cells["lipm_status"] == "drifting"
    assert float(cells["lipm_drift_mm_s"]) == pytest.approx(0.2, rel=0.2)
    assert cells["dlipm_status"] == "settled"
    assert cells["dlipm_drift_mm_s"] == ""
    (line,) = unsettled_lines(rows)
    assert re.match(
        r"0\.1 m, LIPM: did not settle within 7 s \(drift 0\.(19|2)\d* mm/s, drifting", line
    )


def test_targets_beyond_the_fitted_range_are_flagged() -> None:
    rows = _rows(1.0, fit_high=0.08)
    assert [r.extrapolated for r in rows] == [False, False, True]
    assert rows[-1].cells()["extrapolated"] == "1"
    assert "| frontal | 0.1 †" in table1_markdown(rows)
    warnings = plane_verdict("frontal", rows).warnings
    assert warnings[0].startswith("targets 0.1 m lie outside the fitted range [0, 0.08] m")


def test_verdict_met_missed_and_undefined_with_its_reason() -> None:
    met = plane_verdict("frontal", _rows(1.0))
    assert met.met
    assert [b.state for b in met.bars] == ["met", "met"]
    assert met.bars[0].value == pytest.approx(0.0, abs=0.01)
    missed = plane_verdict("frontal", _rows(1.05))  # far: 5 % against 10 %: ratio 0.5
    assert [b.state for b in missed.bars] == ["missed", "met"]
    assert missed.bars[0].value == pytest.approx(0.5, abs=0.01)
    undefined = plane_verdict("frontal", _rows(1.0, lipm_far_rate=2e-4))
    assert [b.state for b in undefined.bars] == ["undefined", "undefined"]
    assert undefined.bars[0].why.startswith("LIPM at 0.1 m did not settle within 7 s")
    assert "undefined: LIPM at 0.1 m did not settle" in undefined.lines()[1]
    assert not undefined.met


def test_a_lipm_error_within_the_noise_leaves_the_ratios_undefined() -> None:
    """Targets of a few millimetres where the LIPM's settled error is a few micrometres,
    inside two standard errors of its settled value (20 µm noise): a ratio of two noise
    draws is no bar met or missed."""
    rows = []
    for x in (0.0, 0.001, 0.002, 0.003):
        rows.append(
            Table1Row(
                "frontal",
                x,
                evaluate_trial("lipm", _trial(x, x, seed=1)),  # the LIPM is exact here
                evaluate_trial("dlipm", _trial(x, x, seed=2)),
                evaluate_trial("linear", _trial(x, x, seed=3)),
                fitted_on=True,
                fit_range_m=(0.0, 0.003),
            )
        )
    verdict = plane_verdict("frontal", rows)
    assert [b.state for b in verdict.bars] == ["undefined", "undefined"]
    assert verdict.bars[0].why.startswith("the LIPM's error at 0.003 m, ")
    assert "within 2 standard errors" in verdict.bars[0].why
    assert "at 3 of 3 targets ≠ 0" in verdict.bars[1].why
    # The same targets with a 3 % LIPM error (90 µm at 3 mm, many standard errors): measured.
    measured = [
        Table1Row(
            r.plane,
            r.zmp_ref,
            evaluate_trial("lipm", _trial(r.zmp_ref, 1.03 * r.zmp_ref, seed=1)),
            r.dlipm,
            r.linear,
            fitted_on=True,
            fit_range_m=(0.0, 0.003),
        )
        for r in rows
    ]
    assert [b.state for b in plane_verdict("frontal", measured).bars] == ["met", "met"]
