"""The ZMP shift's feed-forward over soft servos: closed form, its filter, loads, a pushed OP3."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_disturbances import Push
from zmpkit.robots.registry import get_robot
from zmpkit.walking import online_walk
from zmpkit.walking.zmp_shift_feedforward import (
    SAGITTAL_CUTOFF_PER_STEP_HZ,
    ZmpShiftFeedforward,
)

NAO = get_robot("nao")
MODEL = NAO.ik_model()
SOLES = [NAO.ik_settings.sole_sites[f] for f in ("left", "right")]
JOINTS = NAO.ik_settings.joint_names
K, DT, T_STEP = 20.0, 0.01, 0.5
ALPHA = 1.0 - math.exp(-2.0 * math.pi * (SAGITTAL_CUTOFF_PER_STEP_HZ / T_STEP) * DT)


def _data() -> mujoco.MjData:
    data = mujoco.MjData(MODEL)
    data.qpos[:] = MODEL.qpos0
    data.qpos[2] = 0.3  # the base somewhere above the floor; the axes do not depend on it
    data.qpos[7:] = np.linspace(-0.2, 0.2, MODEL.nq - 7)  # a bent posture, not the zero one
    mujoco.mj_kinematics(MODEL, data)  # as the IK leaves its data after a step
    return data


def _feedforward(data: mujoco.MjData) -> ZmpShiftFeedforward:
    return ZmpShiftFeedforward(MODEL, data, SOLES, JOINTS, K, DT, T_STEP)


def _expected(data: mujoco.MjData, loads: list[float], sx: float, sy: float) -> np.ndarray:
    """Δq = -Σ_i J_r,iᵀ Δm_i / k with MuJoCo's rotational Jacobian of each sole (the module
    takes the hinges' axes instead)."""
    mujoco.mj_kinematics(MODEL, data)
    mujoco.mj_comPos(MODEL, data)
    dofs = [int(MODEL.joint(name).dofadr[0]) for name in JOINTS]
    out = np.zeros(len(JOINTS))
    jacp, jacr = np.zeros((3, MODEL.nv)), np.zeros((3, MODEL.nv))
    for site, fz in zip(SOLES, loads, strict=True):
        mujoco.mj_jacSite(MODEL, data, jacp, jacr, MODEL.site(site).id)
        out -= jacr[:, dofs].T @ np.array([fz * sy, -fz * sx, 0.0]) / K
    return out


@settings(max_examples=25, deadline=None)
@given(
    shift_x=st.floats(-0.05, 0.05),
    shift_y=st.floats(-0.05, 0.05),
    left_n=st.floats(0.0, 60.0),
    right_n=st.floats(0.0, 60.0),
)
def test_the_offsets_are_the_loaded_soles_moments_through_their_jacobians(
    shift_x, shift_y, left_n, right_n
) -> None:
    """Against MuJoCo's Jacobian: -J_rᵀ F_z (Δp_y, -Δp_x, 0) / k summed over the loaded soles."""
    threshold = 5.0
    loads = [f if f >= threshold else 0.0 for f in (left_n, right_n)]
    data = _data()
    targets = np.linspace(-0.3, 0.3, len(JOINTS))
    before = targets.copy()
    feedforward = _feedforward(data)
    feedforward.apply(targets, shift_x, shift_y, np.array([left_n, right_n]), threshold)
    expected = _expected(_data(), loads, ALPHA * shift_x, shift_y)
    np.testing.assert_allclose(targets - before, expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(feedforward.shift_in_world, [ALPHA * shift_x, shift_y])


def test_a_forward_shift_presses_the_loaded_toe_and_leaves_the_swing_leg() -> None:
    """F_z = 40 N on the left sole, Δp_x = 2 cm held: the left ankle pitch takes F Δp_x / k
    toe down once the filter has settled; the right leg, in the air, is not touched."""
    data = _data()
    feedforward = _feedforward(data)
    targets = np.zeros(len(JOINTS))
    for _ in range(2000):  # 20 s: the 1 Hz low-pass has settled
        targets[:] = 0.0
        feedforward.apply(targets, 0.02, 0.0, np.array([40.0, 0.0]), 5.0)
    pitch = JOINTS.index("LAnklePitch")
    axis_y = data.xaxis[MODEL.joint("LAnklePitch").id][1]  # +1: +q pitches the toe down
    assert targets[pitch] == pytest.approx(axis_y * 40.0 * 0.02 / K, rel=1e-9)
    right = [j for j, name in enumerate(JOINTS) if name.startswith("R")]
    assert right
    assert not np.any(targets[right])


def test_the_sagittal_shift_is_low_passed_at_half_the_step_frequency() -> None:
    """x_n = Δp_x (1 - (1 - α)^n), α = 1 - exp(-2π f_c dt), f_c = 0.5 / T_step; y as given."""
    data = _data()
    feedforward = _feedforward(data)
    assert feedforward.sagittal_cutoff_hz == pytest.approx(1.0)
    targets = np.zeros(len(JOINTS))
    for n in range(1, 60):
        feedforward.apply(targets, 0.03, -0.01, np.zeros(2), 5.0)
        expected = 0.03 * (1.0 - (1.0 - ALPHA) ** n)
        assert feedforward.shift_in_world[0] == pytest.approx(expected, rel=1e-12)
        assert feedforward.shift_in_world[1] == -0.01
    assert not np.any(targets)  # no foot loaded: nothing to carry


def test_a_non_finite_shift_never_reaches_the_servos() -> None:
    data = _data()
    feedforward = _feedforward(data)
    targets = np.full(len(JOINTS), 0.1)
    feedforward.apply(targets, math.nan, 0.0, np.array([30.0, 30.0]), 5.0)
    feedforward.apply(targets, 0.0, math.inf, np.array([30.0, 30.0]), 5.0)
    assert np.all(targets == 0.1)
    assert np.all(feedforward.shift_in_world == 0.0)


def test_a_sensor_that_reads_nan_keeps_its_last_load() -> None:
    """Both F-T sensors drop out (NaN) for a tick: the offsets stay those of the last loads."""
    data = _data()
    feedforward = _feedforward(data)
    ticks = []
    for loads in ([30.0, 10.0], [math.nan, math.nan], [30.0, 10.0]):
        targets = np.zeros(len(JOINTS))
        feedforward.apply(targets, 0.0, 0.02, np.array(loads), 5.0)
        ticks.append(targets)
    np.testing.assert_allclose(ticks[1], ticks[0], rtol=1e-12)
    np.testing.assert_allclose(ticks[2], ticks[0], rtol=1e-12)
    assert np.any(ticks[0])


@pytest.mark.parametrize(
    ("stiffness", "period", "step", "what"),
    [
        (0.0, DT, T_STEP, "stiffness_nm_per_rad"),
        (K, -0.01, T_STEP, "control_period_s"),
        (K, DT, math.nan, "step_duration_s"),
    ],
)
def test_bad_settings_are_refused_by_name(stiffness, period, step, what) -> None:
    with pytest.raises(ParameterError, match=what):
        ZmpShiftFeedforward(MODEL, _data(), SOLES, JOINTS, stiffness, period, step)


@pytest.mark.slow
def test_a_soft_robot_stands_a_push_it_fell_from_without_the_feedforward(monkeypatch) -> None:
    """The OP3 (all effects: its factory P gains), 0.1 m/s, 11.91 N along y at the start of
    the seventh step (the sweep's ``push 11.91 N y @ 0``; the NAO's 20 N per kilogram)."""
    config = WalkConfig(
        robot=get_robot("op3"), speed_mps=0.1, duration_s=8.0, seed=0, controller="zmpip",
        pushes=(Push(11.91, 4.0, "y"),), figures=False,
    )  # fmt: skip
    assert not run_walk_trial(config).record.fell
    monkeypatch.setattr(online_walk, "ZMP_SHIFT_FEEDFORWARD", False)
    assert run_walk_trial(config).record.fell
