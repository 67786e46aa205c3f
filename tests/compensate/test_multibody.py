"""Multibody ZMP by inverse dynamics: static CoM projection, finite differences, ideal walk."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.compensate.evaluate import simulate_with_offset
from zmpkit.errors import ModelError, ParameterError
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.robots.nao import make_nao, nao_ik_model
from zmpkit.robots.registry import get_robot
from zmpkit.walking.multibody_zmp import InverseDynamicsZmp, finite_differences

# Measured on the 3 s ideal walk (effects none, 10 ms frames): RMS 11.3 mm (x), 5.7 mm (y)
# between the multibody ZMP of the simulated qpos and the ZMP of the simulated contact
# forces; the 10 ms central differences of a stiff-contact simulation dominate the rest.
IDEAL_WALK_RMS_X_M = 0.015
IDEAL_WALK_RMS_Y_M = 0.008


def _random_static_poses(model: mujoco.MjModel, count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    qpos = np.tile(model.qpos0, (count, 1))
    qpos[:, :3] = rng.uniform([-0.5, -0.5, 0.2], [0.5, 0.5, 0.4], (count, 3))
    quat = rng.normal(size=(count, 4)) * [1.0, 0.1, 0.1, 0.5] + [3.0, 0, 0, 0]
    qpos[:, 3:7] = quat / np.linalg.norm(quat, axis=1, keepdims=True)
    lo, hi = model.jnt_range[1:, 0], model.jnt_range[1:, 1]
    qpos[:, 7:] = rng.uniform(lo, hi, (count, model.nq - 7))
    return qpos


def test_static_pose_zmp_is_the_com_ground_projection() -> None:
    model = nao_ik_model()
    qpos = _random_static_poses(model, 20, seed=1)
    zero = np.zeros((qpos.shape[0], model.nv))
    result = InverseDynamicsZmp(model).from_states(qpos, zero, zero)
    data = mujoco.MjData(model)
    for k, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_forward(model, data)
        np.testing.assert_allclose(result.zmp_in_world[k], data.subtree_com[0, :2], atol=1e-9)
    np.testing.assert_allclose(
        result.force_in_world[:, 2], np.sum(model.body_mass) * -model.opt.gravity[2], rtol=1e-9
    )


def test_finite_differences_are_exact_for_a_quadratic_motion() -> None:
    model = nao_ik_model()
    t = np.arange(7) * 0.01
    qpos = np.tile(model.qpos0, (t.size, 1))
    qpos[:, 0] = 0.3 * t**2
    qpos[:, 10] = 0.1 + 2.0 * t**2
    qvel, qacc = finite_differences(model, qpos, 0.01)
    np.testing.assert_allclose(qvel[1:-1, 0], 0.6 * t[1:-1], atol=1e-12)
    np.testing.assert_allclose(qacc[1:-1, 0], 0.6, atol=1e-9)
    np.testing.assert_allclose(qacc[1:-1, 9], 4.0, atol=1e-9)


def test_bad_input_is_named() -> None:
    model = nao_ik_model()
    with pytest.raises(ParameterError, match=r"qpos must have shape \(N >= 3, 19\)"):
        finite_differences(model, np.zeros((2, 19)), 0.01)
    xml = "<mujoco><worldbody><body><joint/><geom size='0.1'/></body></worldbody></mujoco>"
    fixed = mujoco.MjModel.from_xml_string(xml)
    with pytest.raises(ModelError, match="first joint is free"):
        InverseDynamicsZmp(fixed)


def test_matches_the_contact_force_zmp_on_an_ideal_walk() -> None:
    outcome = simulate_with_offset(
        WalkConfig(get_robot("nao"), duration_s=3.0, effects="none", figures=False)
    )
    record = outcome.record
    assert record is not None
    assert not record.fell
    zmp = InverseDynamicsZmp(make_nao("none").model).from_qpos(record.qpos, 0.01).zmp_in_world
    contact = record.zmp_in_world()
    lo, hi = outcome.summary.window_s
    steady = (record.time_s >= lo) & (record.time_s <= hi)
    rms = np.sqrt(np.nanmean((zmp[steady] - contact[steady]) ** 2, axis=0))
    assert rms[0] < IDEAL_WALK_RMS_X_M
    assert rms[1] < IDEAL_WALK_RMS_Y_M
    linear = outcome.pattern.zmp_reference_in_world[steady] - contact[steady]
    assert rms[0] < 0.5 * np.sqrt(np.nanmean(linear[:, 0] ** 2))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_vectorised_position_differences_equal_mujoco(seed: int) -> None:
    """Free base + hinges: the one-pass difference equals mj_differentiatePos per sample."""
    from zmpkit.robots.nao import nao_ik_model
    from zmpkit.walking.multibody_zmp import (
        _free_base_and_scalar_joints,
        _position_differences,
    )

    model = nao_ik_model()
    assert _free_base_and_scalar_joints(model)  # the one-pass path is the one tested
    rng = np.random.default_rng(seed)
    qpos = np.tile(model.qpos0, (6, 1))
    qpos[:, :3] += rng.normal(0.0, 0.05, (6, 3))
    quats = rng.normal(size=(6, 4))
    quats[1::2] = quats[::2] + rng.normal(0.0, 0.2, (3, 4))  # small and large steps
    quats *= np.where(rng.random((6, 1)) < 0.5, -1.0, 1.0)  # both hemispheres
    qpos[:, 3:7] = quats / np.linalg.norm(quats, axis=1, keepdims=True)
    qpos[:, 7:] += rng.normal(0.0, 0.3, (6, model.nq - 7))
    expected = np.empty((5, model.nv))
    for k in range(5):
        mujoco.mj_differentiatePos(model, expected[k], 1.0, qpos[k], qpos[k + 1])
    np.testing.assert_allclose(_position_differences(model, qpos), expected, atol=1e-10)
