"""TimeSeries: named signals with units and frames; windows, selections and CSV round trips."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from zmpkit.errors import ParameterError
from zmpkit.signals.time_series import Signal, TimeSeries

ZMP_X = Signal("zmp_x", "m", "world")
FZ = Signal("left_fz", "N", "world")
TORQUE = Signal("RKneePitch_torque", "N·m", "joint")


def _series(n: int = 5) -> TimeSeries:
    t = 0.01 * np.arange(n)
    return TimeSeries.from_columns(t, [(ZMP_X, t * 2), (FZ, 10 + t), (TORQUE, -t)])


def test_columns_carry_the_unit_token_of_zmpkit_csv_headers() -> None:
    assert _series().columns == ("zmp_x_m", "left_fz_n", "RKneePitch_torque_nm")
    assert Signal("time", "s").column == "time_s"


def test_a_signal_is_found_by_name_or_by_header() -> None:
    series = _series()
    np.testing.assert_array_equal(series["zmp_x"], series["zmp_x_m"])
    assert series.signal("left_fz_n") == FZ


@pytest.mark.parametrize(
    ("signal", "message"),
    [
        (lambda: Signal("zmp x", "m"), "letters and digits joined by single underscores"),
        (lambda: Signal("zmp_x", "cm"), "unit must be one of s, m, m/s"),
        (lambda: Signal("zmp_x", "m", "floor"), "frame must be one of world, sensor"),
    ],
)
def test_a_bad_signal_is_refused_with_what_is_valid(signal, message) -> None:
    with pytest.raises(ParameterError, match=message):
        signal()


def test_repeated_names_non_increasing_times_and_infinities_are_refused() -> None:
    t = np.array([0.0, 0.1])
    with pytest.raises(ParameterError, match="repeated: zmp_x"):
        TimeSeries(t, np.zeros((2, 2)), (ZMP_X, ZMP_X))
    with pytest.raises(ParameterError, match="sample 1 does not"):
        TimeSeries(np.array([0.0, 0.0]), np.zeros((2, 1)), (ZMP_X,))
    with pytest.raises(ParameterError, match="'left_fz' holds an infinite value"):
        TimeSeries(t, np.array([[0.0, 1.0], [0.0, np.inf]]), (ZMP_X, FZ))
    with pytest.raises(ParameterError, match=r"shape \(len\(time_s\), len\(signals\)\) = \(2, 1\)"):
        TimeSeries(t, np.zeros((2, 2)), (ZMP_X,))


def test_nan_marks_an_undefined_sample_and_is_written_empty(tmp_path) -> None:
    t = np.array([0.0, 0.01])
    series = TimeSeries.from_columns(t, [(ZMP_X, [0.5, np.nan])])
    text = series.write_csv(tmp_path / "s.csv").read_text().splitlines()
    assert text == ["time_s,zmp_x_m", "0,0.5", "0.01,"]


def test_select_and_window_keep_the_descriptions() -> None:
    part = _series(10).select(["left_fz_n", "zmp_x"]).window(0.02, 0.05)
    assert part.names == ("left_fz", "zmp_x")
    np.testing.assert_allclose(part.time_s, [0.02, 0.03, 0.04, 0.05])
    np.testing.assert_allclose(part["zmp_x"], 2 * part.time_s)
    with pytest.raises(ParameterError, match=r"no sample in \[1.0, 2.0\] s"):
        part.window(1.0, 2.0)


@settings(max_examples=50, deadline=None)
@given(
    steps=arrays(np.float64, st.integers(1, 30), elements=st.floats(1e-3, 1.0)),
    scale=st.floats(-1e4, 1e4, allow_nan=False),
)
def test_csv_round_trip_keeps_every_value_to_its_digits(tmp_path_factory, steps, scale) -> None:
    t = np.cumsum(steps)
    values = scale * np.sin(t)
    series = TimeSeries.from_columns(t, [(ZMP_X, values), (FZ, np.abs(values))])
    path = series.write_csv(tmp_path_factory.mktemp("ts") / "s.csv", digits=12)
    table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_allclose(table[:, 0], t, rtol=1e-11)
    np.testing.assert_allclose(table[:, 1:], series.values, rtol=1e-11, atol=1e-300)


@settings(max_examples=50, deadline=None)
@given(n=st.integers(1, 40), a=st.floats(0, 0.5), width=st.floats(0, 0.5))
def test_a_window_holds_exactly_the_samples_inside_it(n, a, width) -> None:
    series = _series(n)
    inside = (series.time_s >= a) & (series.time_s <= a + width)
    if not np.any(inside):
        with pytest.raises(ParameterError):
            series.window(a, a + width)
        return
    window = series.window(a, a + width)
    np.testing.assert_array_equal(window.time_s, series.time_s[inside])
    np.testing.assert_array_equal(window.values, series.values[inside])
