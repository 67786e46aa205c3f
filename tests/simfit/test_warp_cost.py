"""The fit's cost on MuJoCo Warp: only the columns it reads recorded, the joint term summed
per world on the device, against the host path (every column recorded, the cost computed
here) on Warp's CPU device.

The tests marked ``needs_warp`` are skipped where ``mujoco_warp`` is not installed; the
choice of columns and of the joint term's targets is tested without it.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from helpers.simfit_data import SEED, small_case
from zmpkit.robots.nao import make_nao
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.cost_columns import HEIGHT_QPOS, cost_columns, joint_square_error

NAO = get_robot("nao")


def test_cost_columns_are_the_feet_wrenches_the_imu_and_the_height() -> None:
    sim = make_nao("M,G,S", None, seed=0)
    columns = cost_columns(sim)
    assert columns.qpos == (HEIGHT_QPOS,)
    assert len(columns.sensordata) == 6 * len(sim.robot.feet) + 4 < sim.model.nsensordata
    row = np.arange(sim.model.nsensordata, dtype=float)
    kept = row[list(columns.sensordata)]
    for k, foot in enumerate(sim.robot.feet):  # the wrench as the simulation reads it
        np.testing.assert_array_equal(
            -kept[columns.ft_positions[k]], sim.ft_true_of(foot.foot, row)
        )
    quat = sim.sensor_slice(sim.robot.imu.orientation)
    np.testing.assert_array_equal(kept[columns.quat_positions], row[quat])
    assert columns.sites == tuple(sim.model.site(f.site).id for f in sim.robot.feet)


def test_joint_targets_cover_the_union_of_the_experiments_joints() -> None:
    sim = make_nao("M,G,S", None, seed=0)
    a, b, c = sim.joint_names[:3]
    se = joint_square_error(
        [sim, sim],
        [(a, b), (c, a)],
        [np.array([1, 4]), np.array([2])],
        [np.array([[1.0, 2.0], [3.0, 4.0]]), np.array([[5.0, 6.0]])],
    )
    adr = [int(sim.model.jnt_qposadr[sim.model.joint(j).id]) for j in (a, b, c)]
    assert se.columns == tuple(adr)
    np.testing.assert_array_equal(se.targets[0], [[1.0, 2.0, np.nan], [3.0, 4.0, np.nan]])
    np.testing.assert_array_equal(se.targets[1], [[6.0, np.nan, 5.0]])
    assert se.quantum == (sim.robot.sensor_params.encoder_resolution,) * 3  # S on: encoders
    plain = make_nao("M,G", None, seed=0)
    assert joint_square_error([plain], [(a,)], [np.array([1])], [np.zeros((1, 1))]).quantum == (
        0.0,
    )


@pytest.mark.needs_warp
@pytest.mark.slow
def test_device_cost_is_the_host_cost_of_the_same_rollouts(tmp_path) -> None:
    """Two walks of different lengths (two control groups) x three candidates, one of which
    falls, with encoder quantisation (S on): every cost term from the device path equals
    the host path's.

    Warp's CPU device gives the same rollout bit for bit whatever is recorded (tested in
    ``tests/sim/test_warp_batch.py``), so both paths read the same float32 states: the ZMP
    and spectrum terms are computed here from the same numbers (equal), and the joint
    term's sum differs only in the order of its float64 additions (rtol 1e-12, far inside
    float32's 6e-8; the completed fraction and the fall are equal).
    """
    from zmpkit.simfit.cost import experiment_cost
    from zmpkit.simfit.experiments import read_experiments
    from zmpkit.simfit.problem import FitProblem
    from zmpkit.simfit.self_test import SelfTestPlan, record_experiments
    from zmpkit.simfit.warp_batched import costs_batches_warp, simulate_batches_warp

    params, doc, truth = small_case()
    plan = SelfTestPlan(((0.2, 1.5), (0.1, 1.0)), ())
    paths, _ = record_experiments(NAO, plan, doc, params, truth, "M,G", SEED, tmp_path)
    experiments = tuple(read_experiments(paths, NAO))
    problem = FitProblem(NAO, "M,G,S", params, doc, experiments)
    candidates = [[p.nominal for p in params], list(truth), [0.36, 310.0]]
    truths = [problem.truth(c) for c in candidates]
    host = simulate_batches_warp(experiments, truths, "M,G,S", "cpu")
    device = costs_batches_warp(experiments, truths, "M,G,S", "cpu", problem.models_loads)
    falls = 0
    for experiment, signals, terms in zip(experiments, host, device, strict=True):
        for simulated, got in zip(signals, terms, strict=True):
            want = experiment_cost(experiment.signals, simulated, problem.models_loads)
            assert got.completed == want.completed
            if want.completed < 1.0:
                falls += 1
                assert got.total(problem.weights) == want.total(problem.weights)
                continue
            assert want.joint > 0.0
            np.testing.assert_allclose(got.joint, want.joint, rtol=1e-12, atol=0)
            np.testing.assert_allclose(got.joint_rms_rad, want.joint_rms_rad, rtol=1e-12)
            for name in ("zmp", "spectrum"):
                assert getattr(got, name) == getattr(want, name), name
    assert falls >= 1  # the third candidate falls in the longer walk at least
    assert dataclasses.is_dataclass(device[0][0])
