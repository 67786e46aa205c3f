"""zmpkit.sensors.mount and zmpkit.sensors.zmp: closed forms, invariants, error texts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from zmpkit.errors import ParameterError
from zmpkit.sensors import (
    CONTACT_FORCE_THRESHOLD_N,
    SensorMount,
    combined_zmp,
    foot_zmp,
    rpy_to_matrix,
    zmp_series,
)
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sensors.zmp_now import zmp_in_world_now

TOL_M = 1e-12  # [m] for ZMPs within a few metres of the origin: ~1e4 ulp of headroom

angles = st.floats(-math.pi, math.pi)
rpys = st.tuples(angles, angles, angles)
coords = st.floats(-1.0, 1.0)
positions = st.tuples(coords, coords, st.floats(0.0, 0.5))
sole_heights = st.floats(0.0, 0.2)
offsets = st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2))
forces = st.tuples(st.floats(-100.0, 100.0), st.floats(-100.0, 100.0), st.floats(20.0, 1000.0))
mounts = st.builds(SensorMount.from_rpy, positions, rpys, sole_heights)


def point_load_wrench(mount: SensorMount, point_xy, force_in_world) -> np.ndarray:
    """Sensor-frame wrench of a point force at (x, y) on the sole's ground plane [N, N·m]."""
    point_in_world = np.array([*point_xy, mount.ground_height])
    force = np.asarray(force_in_world, dtype=float)
    moment_in_world = np.cross(point_in_world - mount.position, force)
    rotation = mount.rotation
    return np.concatenate([rotation.T @ force, rotation.T @ moment_in_world])


def teo_feet(sole_height: float = 0.010) -> tuple[SensorMount, SensorMount]:
    """TEO-like JR3 mounts: rotated π about x, feet 0.257 m apart (teo-parameters.md §5)."""
    right = SensorMount.from_rpy((0.0, -0.1285, sole_height), (math.pi, 0, 0), sole_height)
    left = SensorMount.from_rpy((0.0, 0.1285, sole_height), (math.pi, 0, 0), sole_height)
    return right, left


# --- SensorMount ------------------------------------------------------------------------


def test_rpy_is_rz_ry_rx() -> None:
    roll, pitch, yaw = 0.3, -0.4, 1.1
    c, s = math.cos, math.sin
    rx = np.array([[1, 0, 0], [0, c(roll), -s(roll)], [0, s(roll), c(roll)]])
    ry = np.array([[c(pitch), 0, s(pitch)], [0, 1, 0], [-s(pitch), 0, c(pitch)]])
    rz = np.array([[c(yaw), -s(yaw), 0], [s(yaw), c(yaw), 0], [0, 0, 1]])
    np.testing.assert_allclose(rpy_to_matrix((roll, pitch, yaw)), rz @ ry @ rx, atol=1e-15)


def test_half_turn_about_x_is_exact() -> None:
    np.testing.assert_array_equal(rpy_to_matrix((math.pi, 0, 0)), np.diag([1.0, -1.0, -1.0]))
    np.testing.assert_array_equal(rpy_to_matrix((0, 0, math.pi / 2)) @ [1, 0, 0], [0, 1, 0])


def test_ground_height_is_sensor_z_minus_sole_height() -> None:
    mount = SensorMount.from_rpy((0.1, 0.2, 0.5), (0, 0, 0), 0.125, name="right")
    assert mount.ground_height == pytest.approx(0.375, abs=1e-15)
    assert mount.name == "right"
    assert not mount.rotation.flags.writeable


def test_non_orthonormal_rotation_rejected() -> None:
    with pytest.raises(ParameterError, match=r"^rotation must be orthonormal .* got max "):
        SensorMount((0, 0, 0), np.diag([1.0, 1.0, 1.1]), 0.01)


def test_reflection_rejected() -> None:
    with pytest.raises(ParameterError, match=r"^rotation must have det \+1 .*, got det = -1$"):
        SensorMount((0, 0, 0), np.diag([1.0, 1.0, -1.0]), 0.01)


def test_negative_sole_height_rejected() -> None:
    with pytest.raises(ParameterError, match=r"^sole_height must be >= 0 m, got -0.01 m$"):
        SensorMount((0, 0, 0), np.eye(3), -0.01)


def test_mount_shape_and_finiteness_rejected() -> None:
    with pytest.raises(ParameterError, match=r"^position must have shape \(3\), got shape \(2,\)"):
        SensorMount((0, 0), np.eye(3), 0.01)
    with pytest.raises(ParameterError, match=r"^position must be finite everywhere"):
        SensorMount((0, math.nan, 0), np.eye(3), 0.01)


# --- closed forms -------------------------------------------------------------------------


@given(mounts, offsets, forces)
def test_point_load_gives_its_point_for_any_mount(mount, offset, force) -> None:
    point = mount.position[:2] + np.array(offset)
    result = foot_zmp(point_load_wrench(mount, point, force), mount)
    assert bool(result.contact)
    assert result.fz == pytest.approx(force[2], rel=1e-12)
    np.testing.assert_allclose(result.zmp, point, rtol=0, atol=TOL_M)


def test_teo_sensor_reading_by_hand() -> None:
    # Rx(π): F_z,world = -F_z,s = 300, τ_y,world = -τ_y,s = 6, F_x,world = F_x,s = 5,
    # τ_x,world = τ_x,s = 1.5, F_y,world = -F_y,s = 2. Eq. 5 with h = 0.01:
    # p_x = 0 - (6 + 0.01·5)/300, p_y = -0.1285 + (1.5 - 0.01·2)/300.
    right, _ = teo_feet()
    result = foot_zmp([5.0, -2.0, -300.0, 1.5, -6.0, 0.7], right)
    np.testing.assert_allclose(result.zmp, [-6.05 / 300, -0.1285 + 1.48 / 300], atol=TOL_M)
    assert result.fz == 300.0


def test_teo_standing_load_reads_negative_sensor_fz() -> None:
    right, _ = teo_feet()
    wrench = point_load_wrench(right, (0.03, -0.11), (0.0, 0.0, 310.0))
    assert wrench[2] == pytest.approx(-310.0)
    np.testing.assert_allclose(foot_zmp(wrench, right).zmp, [0.03, -0.11], atol=TOL_M)


def test_double_support_is_fz_weighted_point() -> None:
    right, left = teo_feet()
    wr = point_load_wrench(right, (0.02, -0.13), (10.0, 5.0, 400.0))
    wl = point_load_wrench(left, (0.05, 0.12), (-3.0, 1.0, 200.0))
    series = zmp_series([0.0], [wr], [wl], right, left)
    # (0.02·400 + 0.05·200)/600 = 0.03; (-0.13·400 + 0.12·200)/600 = -28/600
    np.testing.assert_allclose(series.zmp, [[0.03, -28.0 / 600.0]], atol=TOL_M)
    np.testing.assert_allclose(series.fz_right, [400.0])
    np.testing.assert_allclose(series.fz_left, [200.0])
    assert series.defined.tolist() == [True]


def test_foot_out_of_contact_is_ignored() -> None:
    right, left = teo_feet()
    wr = point_load_wrench(right, (0.02, -0.13), (0.0, 0.0, 400.0))
    wl = np.array([30.0, -20.0, -5.0, 8.0, -9.0, 1.0])  # F_z,world = 5 N < 10 N
    series = zmp_series([0.0], [wr], [wl], right, left)
    assert (series.contact_right.tolist(), series.contact_left.tolist()) == ([True], [False])
    np.testing.assert_allclose(series.zmp, [[0.02, -0.13]], atol=TOL_M)
    with_low_threshold = zmp_series([0.0], [wr], [wl], right, left, contact_threshold_n=4.0)
    assert with_low_threshold.contact_left.tolist() == [True]


def test_threshold_is_inclusive() -> None:
    right, left = teo_feet()
    wl = point_load_wrench(left, (0.0, 0.1), (0.0, 0.0, CONTACT_FORCE_THRESHOLD_N))
    series = zmp_series([0.0], [np.zeros(6)], [wl], right, left)
    assert series.contact_left.tolist() == [True]
    np.testing.assert_allclose(series.zmp, [[0.0, 0.1]], atol=TOL_M)


def test_no_contact_gives_undefined_nan() -> None:
    right, left = teo_feet()
    loaded = point_load_wrench(right, (0.0, -0.1), (0.0, 0.0, 300.0))
    wrenches = np.array([np.zeros(6), loaded, np.zeros(6)])
    series = zmp_series([0.0, 0.001, 0.002], wrenches, np.zeros((3, 6)), right, left)
    assert series.defined.tolist() == [False, True, False]
    assert series.n_undefined == 2
    assert np.isnan(series.zmp_x[[0, 2]]).all()
    assert np.isnan(series.zmp_y[[0, 2]]).all()
    np.testing.assert_allclose([series.zmp_x[1], series.zmp_y[1]], [0.0, -0.1], atol=TOL_M)
    single = foot_zmp(np.zeros(6), right)
    assert not single.contact
    assert np.isnan(single.zmp).all()


def test_three_feet_combine_by_fz() -> None:
    feet = [
        SensorMount.from_rpy((x, y, 0.1), (0, 0, yaw), 0.05)
        for x, y, yaw in [(0.0, 0.0, 0.0), (1.0, 0.0, 1.0), (0.0, 1.0, -2.0)]
    ]
    points = [(0.1, 0.0), (1.0, 0.2), (0.0, 0.9)]
    fz = [100.0, 200.0, 300.0]
    wrenches = [
        point_load_wrench(m, p, (0, 0, f))[None] for m, p, f in zip(feet, points, fz, strict=True)
    ]
    result = combined_zmp(wrenches, feet)
    expected = np.average(points, axis=0, weights=fz)
    np.testing.assert_allclose(result.zmp[0], expected, atol=TOL_M)
    assert result.fz.shape == (3, 1)
    assert result.contact.all()


# --- invariants -----------------------------------------------------------------------------


def _loaded_pair(draw_mounts, draw_offsets, draw_forces):
    right, left = draw_mounts
    wr = point_load_wrench(right, right.position[:2] + draw_offsets[0], draw_forces[0])
    wl = point_load_wrench(left, left.position[:2] + draw_offsets[1], draw_forces[1])
    return right, left, wr, wl


pairs = st.tuples(st.tuples(mounts, mounts), st.tuples(offsets, offsets), st.tuples(forces, forces))


@given(pairs, st.floats(-math.pi, math.pi), positions)
def test_rigid_change_of_world_frame_moves_zmp(pair, yaw, translation) -> None:
    right, left, wr, wl = _loaded_pair(*pair)
    turn = rpy_to_matrix((0.0, 0.0, yaw))

    def moved(m: SensorMount) -> SensorMount:
        return SensorMount(turn @ m.position + translation, turn @ m.rotation, m.sole_height)

    before = zmp_series([0.0], [wr], [wl], right, left).zmp[0]
    after = zmp_series([0.0], [wr], [wl], moved(right), moved(left)).zmp[0]
    np.testing.assert_allclose(after, turn[:2, :2] @ before + translation[:2], atol=TOL_M)


@given(pairs)
def test_double_support_zmp_lies_between_the_feet(pair) -> None:
    right, left, wr, wl = _loaded_pair(*pair)
    both = zmp_series([0.0], [wr], [wl], right, left).zmp[0]
    p_r, p_l = foot_zmp(wr, right).zmp, foot_zmp(wl, left).zmp
    along, to_zmp = p_l - p_r, both - p_r
    assert abs(along[0] * to_zmp[1] - along[1] * to_zmp[0]) <= TOL_M
    assert -TOL_M <= along @ to_zmp <= along @ along + TOL_M


@given(pairs, st.floats(0.05, 20.0))
def test_scaling_the_wrenches_leaves_zmp_unchanged(pair, scale) -> None:
    right, left, wr, wl = _loaded_pair(*pair)
    assume(min(pair[2][0][2], pair[2][1][2]) * scale >= 2 * CONTACT_FORCE_THRESHOLD_N)
    base = zmp_series([0.0], [wr], [wl], right, left).zmp
    scaled = zmp_series([0.0], [scale * wr], [scale * wl], right, left).zmp
    np.testing.assert_allclose(scaled, base, atol=TOL_M)


@settings(max_examples=20)
@given(mounts, st.integers(0, 2**32 - 1))
def test_series_equals_sample_by_sample(mount, seed) -> None:
    rng = np.random.default_rng(seed)
    wrenches = rng.normal(scale=[50, 50, 300, 10, 10, 5], size=(200, 6))
    series = foot_zmp(wrenches, mount)
    for wrench, zmp, contact in zip(wrenches, series.zmp, series.contact, strict=True):
        one = foot_zmp(wrench, mount)
        assert bool(one.contact) == contact
        np.testing.assert_allclose(one.zmp, zmp, rtol=0, atol=TOL_M)


# --- errors ---------------------------------------------------------------------------------


def test_wrench_shape_error_names_argument_and_shapes() -> None:
    right, left = teo_feet()
    time = np.arange(100) * 1e-3
    expected = r"^right_wrench must have shape \(N, 6\) with N = len\(time\) = 100, got \(100, 5\)$"
    with pytest.raises(ParameterError, match=expected):
        zmp_series(time, np.zeros((100, 5)), np.zeros((100, 6)), right, left)
    expected = r"^left_wrench must have shape \(N, 6\) with N = len\(time\) = 100, got \(99, 6\)$"
    with pytest.raises(ParameterError, match=expected):
        zmp_series(time, np.zeros((100, 6)), np.zeros((99, 6)), right, left)
    with pytest.raises(
        ParameterError, match=r"^wrench must have shape \(6,\) or \(N, 6\), got \(3,\)$"
    ):
        foot_zmp([1.0, 2.0, 3.0], right)


def test_non_finite_values_rejected() -> None:
    right, left = teo_feet()
    bad = np.zeros((4, 6))
    bad[2, 3] = math.inf
    # _validate.finite_array prints the index with numpy 2's scalar repr (np.int64(2)) today;
    # both that and the plain (2, 3) are accepted.
    int_2, int_3 = r"(np\.int64\()?2\)?", r"(np\.int64\()?3\)?"
    expected = (
        rf"^left_wrench must be finite everywhere, got non-finite at index \({int_2}, {int_3}\)$"
    )
    with pytest.raises(ParameterError, match=expected):
        zmp_series(np.arange(4.0), np.zeros((4, 6)), bad, right, left)
    with pytest.raises(ParameterError, match=r"^time must be finite everywhere"):
        zmp_series([0.0, math.nan], np.zeros((2, 6)), np.zeros((2, 6)), right, left)


def test_threshold_and_foot_count_errors() -> None:
    right, left = teo_feet()
    message = r"^contact_threshold_n must lie in \[0.01, 10000.0\] N, got 0.0 N$"
    with pytest.raises(ParameterError, match=message):
        zmp_series([0.0], np.zeros((1, 6)), np.zeros((1, 6)), right, left, contact_threshold_n=0)
    with pytest.raises(ParameterError, match=r"got 2 wrenches and 1 mounts$"):
        combined_zmp([np.zeros((1, 6))] * 2, [right])
    expected = (
        r"^wrenches\[1\] must have shape \(N, 6\) with N = len\(wrenches\[0\]\) = 3, got \(2, 6\)$"
    )
    with pytest.raises(ParameterError, match=expected):
        combined_zmp([np.zeros((3, 6)), np.zeros((2, 6))], [right, left])


@given(
    wrench=arrays(np.float64, (2, 9), elements=st.floats(-200.0, 200.0)),
    threshold=st.floats(1.0, 20.0),
)
@settings(max_examples=200, deadline=None)
def test_the_control_loop_zmp_equals_the_vectorised_one(wrench, threshold) -> None:
    """zmp_in_world_now (Python floats, one sample) == zmp_in_world (numpy, a series)."""
    force, moment, origin = wrench[:, :3], wrench[:, 3:6], wrench[:, 6:] * 1e-3
    expected = zmp_in_world(force[None], moment[None], origin[None], threshold)[0]
    got = zmp_in_world_now(force, moment, origin, threshold)
    if np.all(np.isnan(expected)):
        assert got is None
    else:
        assert got is not None
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)
