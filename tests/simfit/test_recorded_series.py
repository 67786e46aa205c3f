"""A fit's recorded signals as a TimeSeries: the same samples, named with units and frames."""

from __future__ import annotations

import numpy as np

from zmpkit.simfit.recorded import RecordedSignals


def test_recorded_signals_as_time_series() -> None:
    t = 0.01 * np.arange(5)
    q_cmd, q_meas = np.outer(t, [1.0, 2.0]), np.outer(t, [1.1, 2.1])
    zmp = np.column_stack([t, -t])
    zmp[2] = np.nan  # no foot in contact
    signals = RecordedSignals(t, ("a", "b"), q_cmd, q_meas, zmp, 0.5 * t)
    series = signals.as_time_series()
    assert series.columns == ("a_cmd_rad", "a_meas_rad", "b_cmd_rad", "b_meas_rad",
                              "zmp_x_m", "zmp_y_m", "trunk_tilt_rad")  # fmt: skip
    np.testing.assert_array_equal(series["b_meas"], q_meas[:, 1])
    np.testing.assert_array_equal(series["zmp_y"], zmp[:, 1])  # NaN stays NaN
    assert series.signal("zmp_x").frame == "world"
