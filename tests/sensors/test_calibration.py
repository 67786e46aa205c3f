"""zmpkit.sensors.calibration: the order of the steps, units, offsets from windows, errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.sensors import (
    SensorMount,
    WrenchCalibration,
    remove_zmp_offset,
    wrench_offset_from_unloaded_window,
    zmp_offset_from_standing_window,
    zmp_series,
)

RAW = np.array([1.0, 2.0, 3.0, 40.0, 50.0, 60.0])


def point_load_wrench(mount: SensorMount, point_xy, force_in_world) -> np.ndarray:
    """Sensor-frame wrench of a point force at (x, y) on the sole's ground plane [N, N·m]."""
    point_in_world = np.array([*point_xy, mount.ground_height])
    force = np.asarray(force_in_world, dtype=float)
    moment_in_world = np.cross(point_in_world - mount.position, force)
    return np.concatenate([mount.rotation.T @ force, mount.rotation.T @ moment_in_world])


def test_identity_by_default() -> None:
    np.testing.assert_array_equal(WrenchCalibration().apply(RAW), RAW)


def test_steps_in_order_permute_sign_unit_gain_offset() -> None:
    calibration = WrenchCalibration(
        offset=(0.5, 0, 0, 0, 0, 1.0),
        gain=(2.0, 1, 1, 1, 1, 3.0),
        axis_order=(1, 0, 2, 4, 3, 5),
        signs=(-1, 1, 1, 1, -1, 1),
        force_unit="daN",
        moment_unit="dN·m",
    )
    # F_x = -1·raw[1]·10·2 - 0.5; F_y = raw[0]·10; τ_x = raw[4]·0.1; τ_y = -raw[3]·0.1;
    # τ_z = raw[5]·0.1·3 - 1
    expected = [-40.5, 10.0, 30.0, 5.0, -4.0, 17.0]
    np.testing.assert_allclose(calibration.apply(RAW), expected, rtol=1e-15)
    np.testing.assert_allclose(calibration.apply(np.tile(RAW, (3, 1))), [expected] * 3)


def test_teo_moment_divided_by_ten_reads_as_decinewton_metres() -> None:
    teo = WrenchCalibration(moment_unit="dN·m")  # W's /10 on M_y (unverified, §5)
    np.testing.assert_allclose(teo.apply(RAW)[3:], [4.0, 5.0, 6.0], rtol=1e-15)


@pytest.mark.parametrize(
    ("force_unit", "moment_unit", "factors"),
    [
        ("N", "N*m", (1.0, 1.0)),
        ("kgf", "Nm", (9.80665, 1.0)),
        ("N", "daN·m", (1.0, 10.0)),
        ("N", "N·mm", (1.0, 1e-3)),
    ],
)
def test_unit_scales(force_unit, moment_unit, factors) -> None:
    wrench = WrenchCalibration(force_unit=force_unit, moment_unit=moment_unit).apply(RAW)
    np.testing.assert_allclose(wrench[:3], RAW[:3] * factors[0], rtol=1e-15)
    np.testing.assert_allclose(wrench[3:], RAW[3:] * factors[1], rtol=1e-15)


def test_unknown_units_list_the_valid_names() -> None:
    with pytest.raises(
        ParameterError, match=r"^unknown force_unit 'lbf'; valid: 'N', 'daN', 'kgf'$"
    ):
        WrenchCalibration(force_unit="lbf")
    valid = "'N·m', 'N\\*m', 'Nm', 'dN·m', 'daN·m', 'N·mm'"
    with pytest.raises(ParameterError, match=rf"^unknown moment_unit 'kN·m'; valid: {valid}$"):
        WrenchCalibration(moment_unit="kN·m")


def test_bad_permutation_signs_gain_rejected() -> None:
    expected = (
        r"^axis_order must be a permutation of \(0, 1, 2, 3, 4, 5\), got \(0, 1, 1, 3, 4, 5\)$"
    )
    with pytest.raises(ParameterError, match=expected):
        WrenchCalibration(axis_order=(0, 1, 1, 3, 4, 5))
    with pytest.raises(
        ParameterError, match=r"^axis_order must be a permutation .*, got \(0, 1\)$"
    ):
        WrenchCalibration(axis_order=(0, 1))
    with pytest.raises(
        ParameterError,
        match=r"^signs must be \+1 or -1 each, got \(1.0, 1.0, 0.5, 1.0, 1.0, 1.0\)$",
    ):
        WrenchCalibration(signs=(1, 1, 0.5, 1, 1, 1))
    with pytest.raises(ParameterError, match=r"^gain must be > 0 each, got \(1.0, 0.0,"):
        WrenchCalibration(gain=(1, 0, 1, 1, 1, 1))


def test_apply_rejects_wrong_shape() -> None:
    with pytest.raises(
        ParameterError, match=r"^wrench_raw must have shape \(6,\) or \(N, 6\), got \(5,\)$"
    ):
        WrenchCalibration().apply(np.zeros(5))


def test_unloaded_window_recovers_the_offset() -> None:
    time = np.arange(1000) * 1e-3
    offset = np.array([3.0, -2.0, 12.5, 0.4, -0.3, 0.05])
    noise = np.where(np.arange(1000) % 2 == 0, 1.0, -1.0)[:, None] * [0.1, 0.1, 0.5, 0.01, 0.01, 0]
    wrenches = offset + noise
    wrenches[500:, 2] += 300.0  # the foot is put down at t = 0.5 s
    estimate = wrench_offset_from_unloaded_window(wrenches, time, (0.0, 0.399))
    np.testing.assert_allclose(estimate, offset, rtol=1e-12, atol=1e-14)
    corrected = WrenchCalibration().with_offset(estimate).apply(wrenches)
    np.testing.assert_allclose(corrected[600:, 2].mean(), 300.0, rtol=1e-12)


def test_empty_window_says_which_and_what_the_data_covers() -> None:
    time = np.arange(100) * 0.01
    expected = r"^window \(5.0, 6.0\) s holds no samples; the data covers t = 0.0 … 0.99 s$"
    with pytest.raises(ParameterError, match=expected):
        wrench_offset_from_unloaded_window(np.zeros((100, 6)), time, (5.0, 6.0))
    with pytest.raises(ParameterError, match=r"^window must be \(t0, t1\) with t0 <= t1"):
        wrench_offset_from_unloaded_window(np.zeros((100, 6)), time, (0.5, 0.1))


def _standing_series(bias_xy):
    right = SensorMount.from_rpy((0.0, -0.1285, 0.01), (math.pi, 0, 0), 0.01)
    left = SensorMount.from_rpy((0.0, 0.1285, 0.01), (math.pi, 0, 0), 0.01)
    time = np.arange(10) * 0.1
    wr = point_load_wrench(right, np.add((0.0, -0.1285), bias_xy), (0, 0, 300.0))
    wl = point_load_wrench(left, np.add((0.0, 0.1285), bias_xy), (0, 0, 300.0))
    right_wrench, left_wrench = np.tile(wr, (10, 1)), np.tile(wl, (10, 1))
    right_wrench[8:], left_wrench[8:] = 0.0, 0.0  # lifted: ZMP undefined at t = 0.8, 0.9 s
    return zmp_series(time, right_wrench, left_wrench, right, left)


def test_standing_window_offset_and_removal() -> None:
    series = _standing_series((0.012, -0.004))
    offset = zmp_offset_from_standing_window(series, None, (0.0, 0.9))  # undefined left out
    np.testing.assert_allclose(offset, [0.012, -0.004], atol=1e-12)
    corrected = remove_zmp_offset(series, offset)
    np.testing.assert_allclose(corrected.zmp[series.defined], 0.0, atol=1e-12)
    assert np.isnan(corrected.zmp[~series.defined]).all()
    np.testing.assert_array_equal(corrected.defined, series.defined)
    expected = zmp_offset_from_standing_window(series.zmp, series.time, (0, 0.9), (0.01, 0.0))
    np.testing.assert_allclose(expected, [0.002, -0.004], atol=1e-12)
    np.testing.assert_allclose(remove_zmp_offset(series.zmp[:2], offset), 0.0, atol=1e-12)


def test_standing_window_errors() -> None:
    series = _standing_series((0.0, 0.0))
    expected = r"^window \(0.8, 0.9\) s holds 2 samples but the ZMP is undefined .* in all of them$"
    with pytest.raises(ParameterError, match=expected):
        zmp_offset_from_standing_window(series, None, (0.8, 0.9))
    with pytest.raises(ParameterError, match=r"^time is required when zmp is an array"):
        zmp_offset_from_standing_window(series.zmp, None, (0.0, 0.5))
    with pytest.raises(
        ParameterError,
        match=r"^zmp must have shape \(N, 2\) with N = len\(time\) = 10, got \(10, 3\)$",
    ):
        zmp_offset_from_standing_window(np.zeros((10, 3)), series.time, (0.0, 0.5))
