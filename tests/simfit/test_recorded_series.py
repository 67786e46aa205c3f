"""A fit's recorded signals as a TimeSeries: the same samples, named with units and frames."""

from __future__ import annotations

import numpy as np

from zmpkit.simfit.recorded import RecordedSignals


def test_recorded_signals_as_time_series() -> None:
    t = 0.01 * np.arange(5)
    q_cmd, q_meas = np.outer(t, [1.0, 2.0]), np.outer(t, [1.1, 2.1])
    zmp = np.column_stack([t, -t])
    zmp[2] = np.nan  # no foot in contact
    force = np.column_stack([20.0 + t, 30.0 - t])
    signals = RecordedSignals(t, ("a", "b"), q_cmd, q_meas, zmp, 0.5 * t, force)
    series = signals.as_time_series()
    assert series.columns == ("a_cmd_rad", "b_cmd_rad", "a_meas_rad", "b_meas_rad",
                              "zmp_x_m", "zmp_y_m", "force_z_right_n", "force_z_left_n",
                              "trunk_tilt_rad")  # fmt: skip
    np.testing.assert_array_equal(series["b_meas"], q_meas[:, 1])
    np.testing.assert_array_equal(series["zmp_y"], zmp[:, 1])  # NaN stays NaN
    np.testing.assert_array_equal(series["force_z_left"], force[:, 1])
    assert series.signal("zmp_x").frame == "world"
    assert series.signal("force_z_right").unit == "N"


def test_forces_not_recorded_read_as_nan() -> None:
    """A record made without the feet's forces (a source that has none) holds NaN there."""
    t = 0.01 * np.arange(3)
    q = np.zeros((3, 1))
    record = RecordedSignals(t, ("a",), q, q, np.zeros((3, 2)), t)
    assert record.force_z_n.shape == (3, 2)
    assert np.all(np.isnan(record.force_z_n))


def test_a_record_is_its_time_series_and_pickles_as_one_table() -> None:
    """The arrays the cost compares are views of the record's series (no copy), and a record
    sent to a worker process travels as that one table."""
    import pickle

    t = 0.01 * np.arange(4)
    q_cmd, q_meas = np.outer(t, [1.0, 2.0]), np.outer(t, [1.5, 2.5])
    record = RecordedSignals(t, ("a", "b"), q_cmd, q_meas, np.column_stack([t, t]), -t)
    views = (record.q_cmd_rad, record.q_meas_rad, record.zmp_m, record.force_z_n)
    for view in (*views, record.trunk_tilt_rad):
        assert np.shares_memory(view, record.series.values)
        assert not view.flags.writeable
    again = pickle.loads(pickle.dumps(record))
    np.testing.assert_array_equal(again.q_meas_rad, q_meas)
    assert np.shares_memory(again.zmp_m, again.series.values)
    head = record.head(2)
    np.testing.assert_array_equal(head.trunk_tilt_rad, -t[:2])
    empty = RecordedSignals(np.zeros(0), ("a", "b"), np.zeros((0, 2)), np.zeros((0, 2)),
                            np.zeros((0, 2)), np.zeros(0))  # fmt: skip
    assert len(empty.series) == 0  # a rollout that diverged before its first sample
