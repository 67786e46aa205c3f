"""A step trial's record as a TimeSeries: every sample, each signal with its unit and frame."""

from __future__ import annotations

import numpy as np

from zmpkit.experiments.trial_record import StepTrialRecord


def test_step_trial_record_as_time_series_keeps_every_sample() -> None:
    n, rng = 6, np.random.default_rng(1)
    record = StepTrialRecord(
        plane="sagittal", target_m=0.02, t_step_s=0.01, lean_angle_rad=0.03, lean_length_m=0.8,
        joint_names=("a", "b"), time=0.01 * np.arange(n), right_wrench=rng.normal(size=(n, 6)),
        left_wrench=rng.normal(size=(n, 6)), encoders=rng.normal(size=(n, 2)),
        commanded=rng.normal(size=(n, 2)), imu=rng.normal(size=(n, 10)),
    )  # fmt: skip
    series = record.as_time_series()
    assert len(series.signals) == 12 + 4 + 10
    np.testing.assert_array_equal(series["left_tz"], record.left_wrench[:, 5])
    np.testing.assert_array_equal(series["b_cmd_rad"], record.commanded[:, 1])
    np.testing.assert_array_equal(series["quat_w"], record.imu[:, 6])
    assert series.signal("right_tx").unit == "N·m"
    assert series.signal("right_fx").frame == "sensor"
    assert series.signal("accel_z").column == "accel_z_mps2"
