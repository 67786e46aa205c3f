"""ZMP feedback in trials: the reader, the injected faults, and the loop on the virtual TEO."""

from __future__ import annotations

import math

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.experiments import StepExperimentConfig, design_lean_model, run_step_trial
from zmpkit.experiments.ft_faults import FAULT_KINDS, FtFaults
from zmpkit.experiments.response import measured_zmp
from zmpkit.experiments.zmp_reading import ZmpReader
from zmpkit.identify import ErrorModel
from zmpkit.io import feet_from_mapping
from zmpkit.pipelines.balance import BalanceConfig, _factory
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N, SensorMount

PLANE, TARGET_M, HOLD_S = "sagittal", 0.06, 30.0  # 5 time constants of the PI rule
# a schedule whose slope is 25 % too steep: the DLIPM alone lands ~20 % short
MIS_SCHEDULED = ErrorModel("quadratic", (0.834, 1.024 * 1.25, 0.0))


# --- faults and reader, no simulation ---------------------------------------------------------


def test_faults_come_in_bursts_taking_the_kinds_in_turn() -> None:
    faults = FtFaults(("dropout", "nan"), start_s=1.0, period_s=1.0, duration_s=0.1)
    assert faults.kind_at(0.5) == ""
    assert faults.kind_at(1.05) == "dropout"
    assert faults.kind_at(1.15) == ""
    assert faults.kind_at(2.05) == "nan"
    assert faults.kind_at(3.0) == "dropout"


def test_fault_kinds_corrupt_the_reading() -> None:
    faults = {k: FtFaults((k,), start_s=0.1) for k in FAULT_KINDS}
    wrench = [1.0, -2.0, 300.0, 0.5, 0.5, 0.0]
    assert not faults["dropout"].apply(0.15, list(wrench))
    spiked = list(wrench)
    assert faults["spike"].apply(0.15, spiked)
    assert spiked[3:5] == [40.5, 40.5]
    nan = list(wrench)
    faults["nan"].apply(0.15, nan)
    assert all(math.isnan(v) for v in nan)
    saturated = list(wrench)
    faults["saturation"].apply(0.15, saturated)
    assert saturated[:3] == [2000.0, -2000.0, 2000.0]
    untouched = list(wrench)
    assert faults["nan"].apply(0.05, untouched)
    assert untouched == wrench


def test_fault_error_texts() -> None:
    with pytest.raises(ParameterError, match="dropout, spike, nan, saturation; got 'glitch'"):
        FtFaults(("glitch",))
    with pytest.raises(ParameterError, match="duration_s"):
        FtFaults(("nan",), period_s=0.1, duration_s=0.2)


class _Source:
    """A fixed load of 300 N per foot at x = 0.02 m under each sensor (identity mounts)."""

    def ft(self, foot: str) -> list[float]:
        return [0.0, 0.0, 300.0, 0.0, -0.02 * 300.0, 0.0]


@pytest.mark.parametrize("kind", FAULT_KINDS)
def test_reader_removes_the_offset_and_turns_faults_into_none(kind: str) -> None:
    mounts = {
        side: SensorMount.from_rpy((0.0, y, 0.01), (0.0, 0.0, 0.0), 0.01, side)
        for side, y in (("right", -0.1), ("left", 0.1))
    }
    reader = ZmpReader(
        _Source(), PLANE, mounts, CONTACT_FORCE_THRESHOLD_N, FtFaults((kind,), start_s=1.0)
    )
    for _ in range(10):
        reader.observe_startup()
    assert reader.read(0.5) == pytest.approx(0.0, abs=1e-12)  # 0.02 m offset removed
    assert reader.read(1.05) is None  # in a burst
    assert reader.read(1.5) == pytest.approx(0.0, abs=1e-12)
    if kind != "dropout":
        assert sum(reader.gate.rejected.values()) == 1


# --- trials on the virtual TEO ---------------------------------------------------------------


def _trial_zmp(kind: str, faults: tuple[str, ...] = ()) -> tuple[float, str]:
    """Mean measured ZMP over the trial's last second [m] and how its hold ended."""
    config = BalanceConfig.quick(workers=1, dlipm_feedback=True)
    lean_length = design_lean_model(config.robot, PLANE).lean_length_m
    factory = _factory(kind, MIS_SCHEDULED, lean_length, PLANE, config, (0.0, 0.1))
    experiment = StepExperimentConfig(
        robot=config.robot, targets_m=(TARGET_M,), plane=PLANE, hold_s=HOLD_S, faults=faults
    )
    record = run_step_trial(experiment, TARGET_M, factory)
    mounts = feet_from_mapping(config.robot.feet_mounts())
    startup = (experiment.t_step_s - experiment.startup_window_s, experiment.t_step_s)
    zmp = measured_zmp(record, mounts, startup, config.robot.contact_force_threshold_n)
    since = record.time - record.t_step_s
    last = zmp[since > since[-1] - 1.0]
    assert np.all(np.isfinite(last))
    return float(np.mean(last)), record.hold_end


@pytest.fixture(scope="module")
def fault_free_loop() -> tuple[float, str]:
    """The fault-free feedback trial, run once for the tests that compare against it."""
    return _trial_zmp("dlipm_fb")


@pytest.mark.slow
def test_feedback_removes_the_offset_of_a_mis_scheduled_dlipm(
    fault_free_loop: tuple[float, str],
) -> None:
    open_loop, _ = _trial_zmp("dlipm")
    closed, end = fault_free_loop
    assert abs(open_loop - TARGET_M) > 0.15 * TARGET_M  # measured: 0.0479 m, 20 % short
    assert abs(closed - TARGET_M) < 0.02 * TARGET_M  # measured: 0.0599 m, 0.2 %
    assert end == "hold"


@pytest.mark.parametrize("kind", FAULT_KINDS)
@pytest.mark.slow
def test_feedback_loop_survives_each_fault(kind: str, fault_free_loop: tuple[float, str]) -> None:
    clean, _ = fault_free_loop
    faulty, end = _trial_zmp("dlipm_fb", (kind,))
    assert end == "hold"  # no tipping
    assert faulty == pytest.approx(clean, abs=0.001)  # within 1 mm of the fault-free loop
    assert abs(faulty - TARGET_M) < 0.02 * TARGET_M
