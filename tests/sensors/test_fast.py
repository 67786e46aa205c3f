"""zmpkit.sensors.fast: the scalar path equals the vectorised one and the closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.sensors import (
    CONTACT_FORCE_THRESHOLD_N,
    DoubleSupportZmp,
    SensorMount,
    moment_coefficients,
    zmp_series,
)

TOL_M = 1e-12  # [m], for closed-form points within a few metres of the origin
REL = 1e-12  # relative to the magnitude of the terms summed, see _term_scale

angles = st.floats(-math.pi, math.pi)
right_angles = st.sampled_from([0.0, math.pi / 2, math.pi, -math.pi / 2])
rpys = st.one_of(st.tuples(angles, angles, angles), st.tuples(right_angles, right_angles, angles))
positions = st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(0.0, 0.5))
mounts = st.builds(SensorMount.from_rpy, positions, rpys, st.floats(0.0, 0.2))
components = st.floats(-500.0, 500.0)
wrenches = st.lists(components, min_size=6, max_size=6)


def point_load_wrench(mount: SensorMount, point_xy, force_in_world) -> list[float]:
    """Sensor-frame wrench of a point force at (x, y) on the sole's ground plane [N, N·m]."""
    point_in_world = np.array([*point_xy, mount.ground_height])
    force = np.asarray(force_in_world, dtype=float)
    moment_in_world = np.cross(point_in_world - mount.position, force)
    rotation = mount.rotation
    return np.concatenate([rotation.T @ force, rotation.T @ moment_in_world]).tolist()


def teo_feet() -> tuple[SensorMount, SensorMount]:
    """TEO-like JR3 mounts: rotated π about x, 0.01 m above the sole, feet 0.257 m apart."""
    right = SensorMount.from_rpy((0.0, -0.1285, 0.01), (math.pi, 0, 0), 0.01, "right")
    left = SensorMount.from_rpy((0.0, 0.1285, 0.01), (math.pi, 0, 0), 0.01, "left")
    return right, left


def _term_scale(feet_in_contact, fz_total: float) -> float:
    """Σ |c_j w_j| / |Σ F_z| over (mount, wrench) pairs: the size of the rounded sums [m]."""
    total = sum(np.abs(moment_coefficients(m)[:, 1:]).T @ np.abs(w) for m, w in feet_in_contact)
    return float(np.max(total)) / abs(fz_total)


@given(mounts, mounts, wrenches, wrenches)
def test_fast_equals_vectorised_for_any_mounting(right, left, wr, wl) -> None:
    series = zmp_series([0.0], [wr], [wl], right, left)
    for fz in (series.fz_right[0], series.fz_left[0]):
        assume(abs(fz - CONTACT_FORCE_THRESHOLD_N) > 1e-6)
    fast = DoubleSupportZmp(right, left)
    result = fast(wr, wl)
    assert fast.contacts(wr, wl) == (series.contact_right[0], series.contact_left[0])
    if not series.defined[0]:
        assert result is None
        return
    assert result is not None
    contact = (series.contact_right[0], series.contact_left[0])
    feet = [(m, w) for m, w, c in zip((right, left), (wr, wl), contact, strict=True) if c]
    fz_r, fz_l = series.fz_right[0], series.fz_left[0]
    fz_total = fz_r * contact[0] + fz_l * contact[1]
    scale = _term_scale(feet, fz_total)
    np.testing.assert_allclose(result, series.zmp[0], rtol=REL, atol=REL * scale)


@given(mounts, mounts, st.floats(-0.2, 0.2), st.floats(20.0, 1000.0), st.floats(20.0, 1000.0))
def test_point_loads_give_the_weighted_point(right, left, dx, fz_r, fz_l) -> None:
    p_r, p_l = right.position[:2] + dx, left.position[:2] - dx
    wr = point_load_wrench(right, p_r, (dx * 100, -dx * 50, fz_r))
    wl = point_load_wrench(left, p_l, (-dx * 30, dx * 70, fz_l))
    expected = (p_r * fz_r + p_l * fz_l) / (fz_r + fz_l)
    np.testing.assert_allclose(DoubleSupportZmp(right, left)(wr, wl), expected, atol=TOL_M)


def test_single_support_and_no_contact() -> None:
    right, left = teo_feet()
    fast = DoubleSupportZmp(right, left)
    loaded_right = point_load_wrench(right, (0.04, -0.11), (3.0, 2.0, 350.0))
    loaded_left = point_load_wrench(left, (-0.02, 0.15), (3.0, 2.0, 350.0))
    lifted = [1.0, -2.0, -4.0, 0.5, 0.3, 0.0]  # F_z,world = 4 N < 10 N
    np.testing.assert_allclose(fast(loaded_right, lifted), (0.04, -0.11), atol=TOL_M)
    np.testing.assert_allclose(fast(lifted, loaded_left), (-0.02, 0.15), atol=TOL_M)
    assert fast.contacts(loaded_right, lifted) == (True, False)
    assert fast.contacts(lifted, loaded_left) == (False, True)
    assert fast(lifted, lifted) is None
    assert fast.contacts(lifted, lifted) == (False, False)
    assert DoubleSupportZmp(right, left, contact_threshold_n=3.0).contacts(lifted, lifted) == (
        True,
        True,
    )


def test_teo_mount_keeps_only_nonzero_coefficients() -> None:
    fast = DoubleSupportZmp(*teo_feet())
    assert "fz_r = -r2\n" in fast.source
    assert "fz_l = -l2\n" in fast.source
    body = fast.source.split("def contacts")[0]
    assert "r5" not in body.split("= right_wrench")[1]  # τ_z never enters the ZMP


def test_accepts_lists_tuples_and_arrays() -> None:
    fast = DoubleSupportZmp(*teo_feet())
    wrench = [5.0, -2.0, -300.0, 1.5, -6.0, 0.7]
    expected = fast(wrench, wrench)
    assert isinstance(expected[0], float)
    assert fast(tuple(wrench), tuple(wrench)) == expected
    np.testing.assert_allclose(fast(np.array(wrench), np.array(wrench)), expected, rtol=0, atol=0)
    assert fast.compute(wrench, wrench) == expected


def test_threshold_validated() -> None:
    message = r"^contact_threshold_n must lie in \[0.01, 10000.0\] N, got -1.0 N$"
    with pytest.raises(ParameterError, match=message):
        DoubleSupportZmp(*teo_feet(), contact_threshold_n=-1.0)
