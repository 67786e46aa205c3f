"""Batched open-loop rollouts (MuJoCo thread pool) against the serial, step-by-step path."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.simfit_data import record_walk, small_case
from zmpkit.robots.registry import get_robot
from zmpkit.sim.sensing import sample_series
from zmpkit.simfit.batched import simulate_batch, simulate_batches
from zmpkit.simfit.experiments import StepExperiment, WalkExperiment, read_experiments
from zmpkit.simfit.open_loop import posed_simulation, posed_simulations
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import (
    base_truth_path,
    load_robot_truth,
    load_truth_doc,
    truth_doc_with,
)

NAO = get_robot("nao")
TEO = get_robot("teo")
_FIELDS = ("time_s", "q_cmd_rad", "q_meas_rad", "zmp_m", "force_z_n", "trunk_tilt_rad")


def _assert_same(batched: RecordedSignals, serial: RecordedSignals) -> None:
    """Bit for bit: same rows, same numbers (NaN where the serial path has NaN)."""
    assert batched.joint_names == serial.joint_names
    for name in _FIELDS:
        np.testing.assert_array_equal(getattr(batched, name), getattr(serial, name), err_msg=name)


@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> WalkExperiment:
    folder = record_walk(tmp_path_factory.mktemp("batched_walk"))
    (experiment,) = read_experiments([folder], NAO)
    assert isinstance(experiment, WalkExperiment)
    return experiment


@pytest.fixture(scope="module")
def step(tmp_path_factory: pytest.TempPathFactory) -> StepExperiment:
    from zmpkit.experiments import StepExperimentConfig, run_step_sweep

    config = StepExperimentConfig(
        TEO, targets_m=(0.04,), effects="M,G,F,S", settle_s=2.0, hold_s=1.0
    )
    dataset = run_step_sweep(config, tmp_path_factory.mktemp("batched_step"), workers=1)
    (experiment,) = read_experiments([Path(dataset.path)], TEO)
    assert isinstance(experiment, StepExperiment)
    return experiment


@pytest.mark.parametrize("effects", ["M,G,S", "M,G"])
@pytest.mark.slow
def test_walks_equal_the_serial_path(walk: WalkExperiment, effects: str) -> None:
    params, doc, truth = small_case()
    # nominal, the hidden truth, a candidate that falls, one that diverges at once
    values = [[p.nominal for p in params], list(truth), [0.36, 310.0], [0.7, 1.0e7]]
    truths = [load_robot_truth(NAO, truth_doc_with(doc, params, v)) for v in values]
    batched = simulate_batch(walk, truths, effects, nthread=2)
    serial = [simulate_experiment(walk, t, effects) for t in truths]
    lengths = [len(s.time_s) for s in serial]
    assert lengths[0] == lengths[1] == len(walk.signals.time_s)
    assert 0 < lengths[2] < lengths[0]  # it fell: the record ends at the fall
    assert lengths[3] == 0  # it diverged: no signals
    for b, s in zip(batched, serial, strict=True):
        _assert_same(b, s)


@pytest.mark.slow
def test_step_trials_equal_the_serial_path(step: StepExperiment) -> None:
    params = default_parameters(TEO, "M,G", ("pid_kp", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(TEO, None))
    values = [[30000.0, 40000.0], [5000.0, 8000.0], [150000.0, 200000.0], [30000.0, 1.0e12]]
    truths = [load_robot_truth(TEO, truth_doc_with(doc, params, v)) for v in values]
    batched = simulate_batch(step, truths, "M,G,F,S", nthread=2)
    serial = [simulate_experiment(step, t, "M,G,F,S") for t in truths]
    assert len(serial[0].time_s) == len(step.signals.time_s)
    assert len(serial[3].time_s) < len(step.signals.time_s)  # diverged: the rows before it
    for b, s in zip(batched, serial, strict=True):
        _assert_same(b, s)


def test_no_candidates_give_no_signals(walk: WalkExperiment) -> None:
    assert simulate_batch(walk, [], "M,G,S") == []
    assert simulate_batches([walk, walk], [], "M,G,S") == [[], []]


@pytest.mark.slow
def test_experiments_sharing_a_compiled_model_equal_the_serial_path(walk: WalkExperiment) -> None:
    """A candidate's second experiment starts from a copy of its first one's model."""
    params, doc, truth = small_case()
    values = [list(truth), [0.36, 310.0]]  # one that walks, one that falls
    truths = [load_robot_truth(NAO, truth_doc_with(doc, params, v)) for v in values]
    batched = simulate_batches([walk, walk], truths, "M,G,S", nthread=2)
    serial = [simulate_experiment(walk, t, "M,G,S") for t in truths]
    for per_experiment in batched:
        for b, s in zip(per_experiment, serial, strict=True):
            _assert_same(b, s)


def test_posed_simulations_own_their_models(walk: WalkExperiment) -> None:
    params, doc, truth = small_case()
    truths = [load_robot_truth(NAO, truth_doc_with(doc, params, list(truth)))]
    (first,), (second,) = posed_simulations([walk, walk], truths, "M,G,S")
    alone = posed_simulation(walk, truths[0], "M,G,S")
    assert first.model is not second.model
    for sim in (first, second):  # each as posed_simulation builds it, state and model
        np.testing.assert_array_equal(sim.data.qpos, alone.data.qpos)
        np.testing.assert_array_equal(sim.model.actuator_gainprm, alone.model.actuator_gainprm)
    first.model.actuator_gainprm[:] *= 2.0  # a change to one candidate's model stays there
    np.testing.assert_array_equal(second.model.actuator_gainprm, alone.model.actuator_gainprm)


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(0, 40),
    seed=st.integers(0, 2**32 - 1),
    scale=st.floats(0.0, 500.0),
    fresh=st.booleans(),
)
def test_sample_series_is_repeated_sampling(n: int, seed: int, scale: float, fresh: bool) -> None:
    from zmpkit.robots.nao import make_nao

    sim = make_nao("S", None, seed=seed % 1000)
    channels = [sim.ft_channel("right"), sim.ft_channel("left")]
    if fresh:
        for c in channels:
            c._state = None  # as before the first sample
    reference = [copy.deepcopy(c) for c in channels]
    wrenches = scale * np.random.default_rng(seed).standard_normal((2, n, 6))
    expected = np.array(
        [[c.sample(w) for w in ws] for c, ws in zip(reference, wrenches, strict=True)]
    )
    got = sample_series(channels, wrenches)
    np.testing.assert_array_equal(got, expected.reshape(got.shape))
    for c, r in zip(channels, reference, strict=True):
        np.testing.assert_array_equal(c.output, r.output)
