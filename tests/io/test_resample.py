"""Resampling onto one clock: exact at source samples, linear between, no extrapolation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io import FtLog, ImuLog, JointLog, RobotLog, resample


def _ft(time: np.ndarray) -> FtLog:
    right = np.column_stack([2.0 * time + i for i in range(6)])
    return FtLog(time, right, -right, source="ft.csv")


def _log() -> RobotLog:
    ft = _ft(np.arange(0.0, 1.0001, 0.001))
    tj = np.arange(0.0005, 1.0, 0.002)
    joints = JointLog(tj, ("a",), (3.0 * tj)[:, None], None, "joints")
    ti = np.arange(0.01, 0.99, 0.004)
    angle = ti  # rotation about z by angle [rad]
    quat = np.column_stack([0 * ti, 0 * ti, np.sin(angle / 2), np.cos(angle / 2)])
    quat[1::2] *= -1.0  # q and -q alternate: one rotation
    imu = ImuLog(ti, np.column_stack([ti, ti, ti]), np.zeros((ti.size, 3)), quat, "imu")
    return RobotLog(ft=ft, joints=joints, imu=imu, source="log")


def test_rate_grid_spans_only_what_every_stream_covers() -> None:
    out = resample(_log(), rate_hz=100.0)
    t = out.ft.time
    assert t[0] == pytest.approx(0.01)
    assert t[-1] <= 0.9985
    for stream in (out.ft, out.joints, out.imu):
        np.testing.assert_array_equal(stream.time, t)
    np.testing.assert_allclose(out.ft.right_wrench[:, 0], 2.0 * t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(out.joints.position[:, 0], 3.0 * t, rtol=0, atol=1e-12)
    yaw = 2.0 * np.arctan2(out.imu.orientation_xyzw[:, 2], out.imu.orientation_xyzw[:, 3])
    np.testing.assert_allclose(np.abs(yaw), t, atol=1e-6)  # nlerp across the sign flips
    np.testing.assert_allclose(np.linalg.norm(out.imu.orientation_xyzw, axis=1), 1.0)


def test_target_times_on_source_samples_give_them_exactly() -> None:
    ft = _ft(np.linspace(0.0, 1.0, 11))
    out = resample(ft, time=ft.time[2:9])
    assert isinstance(out, FtLog)
    np.testing.assert_array_equal(out.right_wrench, ft.right_wrench[2:9])
    np.testing.assert_array_equal(out.left_wrench, ft.left_wrench[2:9])


def test_no_extrapolation() -> None:
    ft = _ft(np.linspace(0.0, 1.0, 11))
    with pytest.raises(
        ParameterError,
        match=r"ft covers t = 0 … 1 s; target times 0.5 … 1.5 s would need extrapolation",
    ):
        resample(ft, time=[0.5, 1.5])


def test_gap_longer_than_the_limit_is_an_error_naming_it() -> None:
    time = np.concatenate([np.arange(0.0, 0.1, 0.01), np.arange(1.0, 1.1, 0.01)])
    ft = _ft(time)
    with pytest.raises(
        InputFileError,
        match=r"ft.csv: ft has a gap of 0.91 s \(t = 0.09 … 1 s\), longer than max_gap_s = 0.1 s",
    ):
        resample(ft, rate_hz=50.0)
    out = resample(ft, rate_hz=50.0, max_gap_s=math.inf)
    np.testing.assert_allclose(out.right_wrench[:, 0], 2.0 * out.time, rtol=0, atol=1e-12)


def test_streams_that_do_not_overlap() -> None:
    t = np.linspace(0.0, 1.0, 5)
    joints = JointLog(t + 5.0, ("a",), t[:, None])
    with pytest.raises(InputFileError, match=r"log: the streams do not overlap in time: ft covers"):
        resample(RobotLog(ft=_ft(t), joints=joints, source="log"), rate_hz=10.0)


def test_needs_exactly_one_clock() -> None:
    with pytest.raises(ParameterError, match=r"give exactly one of rate_hz \[Hz\] and time \[s\]"):
        resample(_ft(np.linspace(0.0, 1.0, 3)))
    with pytest.raises(ParameterError, match=r"time must be a non-empty, strictly increasing"):
        resample(_ft(np.linspace(0.0, 1.0, 3)), time=[0.5, 0.2])


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(st.floats(0.001, 0.01), min_size=2, max_size=30),
    values=st.lists(st.floats(-1e3, 1e3), min_size=31, max_size=31),
    rate=st.floats(50.0, 2000.0),
)
def test_values_stay_between_their_neighbours(
    steps: list[float], values: list[float], rate: float
) -> None:
    time = np.concatenate([[0.0], np.cumsum(steps)])
    v = np.array(values[: time.size])
    ft = FtLog(time, np.tile(v[:, None], (1, 6)), np.zeros((time.size, 6)))
    out = resample(ft, rate_hz=rate, max_gap_s=math.inf)
    i = np.clip(np.searchsorted(time, out.time, side="right") - 1, 0, time.size - 2)
    low = np.minimum(v[i], v[i + 1]) - 1e-9
    high = np.maximum(v[i], v[i + 1]) + 1e-9
    assert np.all((out.right_wrench[:, 0] >= low) & (out.right_wrench[:, 0] <= high))
    assert out.time[0] == 0.0
    assert out.time[-1] <= time[-1]
