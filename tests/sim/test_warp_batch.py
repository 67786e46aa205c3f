"""MuJoCo Warp batched rollouts against CPU MuJoCo (``mujoco.rollout``), on Warp's CPU device.

The tests marked ``needs_warp`` are skipped where ``mujoco_warp`` is not installed
(``pip install 'zmpkit[gpu]'``); ``rollout_warp`` imports MuJoCo Warp before it checks its
arguments, so only the error that says how to install it runs without it.

Tolerances come from measurements on the virtual NAO with M, G and S on (dcmotor actuators
and tendon gears), 300 steps of 1 ms under a 2 Hz setpoint wave: MuJoCo Warp computes in
float32 and its largest deviations from float64 CPU MuJoCo were 4.1e-7 rad in qpos,
1.4e-4 rad/s in qvel, 1.3e-6 in act (of 0.2) and 8e-5 of each sensor's range (F-T force
8.3e-3 N of 127 N). The tolerances sit 10-25 times above those; the two parameter sets
move the robot 1.7e-2 rad apart, over 1000 times the qpos tolerance.
"""

from __future__ import annotations

import copy
import sys

import mujoco
import numpy as np
import pytest
from mujoco import rollout

from zmpkit.errors import ParameterError
from zmpkit.robots.nao import make_nao
from zmpkit.robots.registry import get_robot
from zmpkit.sim.warp_batch import rollout_warp

FULL = mujoco.mjtState.mjSTATE_FULLPHYSICS
NSTEP = 300
RECORD_EVERY = 3
QPOS_TOL = 1e-5  # [rad or m], 25 x the measured 4.1e-7
QVEL_TOL = 2e-3  # [rad/s or m/s], 14 x the measured 1.4e-4
ACT_TOL = 2e-5  # [rad at the motor], 15 x the measured 1.3e-6
SENSOR_REL_TOL = 1e-3  # of each sensor's largest |reading|, 12 x the measured 8e-5


@pytest.fixture(scope="module")
def nao() -> tuple[mujoco.MjModel, np.ndarray, np.ndarray]:
    """NAO (M,G,S) model, its standing state, and 300 steps of a 2 Hz setpoint wave.

    The robot stands in its zero pose (legs straight), whose setpoints are 0; every
    motor's setpoint swings ±0.05 rad at the joint (times the gear ratio at the motor).
    """
    sim = make_nao("M,G,S", None, seed=0)
    model = sim.model
    state = np.empty(mujoco.mj_stateSize(model, FULL))
    mujoco.mj_getState(model, sim.data, state, FULL)
    t = (np.arange(NSTEP) + 1) * model.opt.timestep
    wave = 0.05 * np.outer(np.sin(2 * np.pi * 2.0 * t), model.actuator_gear[:, 0])
    return model, state, wave


def variant(model: mujoco.MjModel, **scale: float) -> mujoco.MjModel:
    """A copy of ``model`` with the named fields multiplied by ``scale``."""
    other = copy.deepcopy(model)
    for name, factor in scale.items():
        getattr(other, name)[:] *= factor
    return other


def cpu_rows(model: mujoco.MjModel, state: np.ndarray, control: np.ndarray):
    """CPU MuJoCo's state and sensordata after every RECORD_EVERY-th step."""
    states, sensors = rollout.rollout(model, mujoco.MjData(model), state, control)
    rows = slice(RECORD_EVERY - 1, None, RECORD_EVERY)
    return states[0, rows], sensors[0, rows]


def assert_close_to_cpu(model, warp_state, warp_sensors, cpu_state, cpu_sensors) -> None:
    nq, nv = model.nq, model.nv
    blocks = {"qpos": (1, 1 + nq, QPOS_TOL), "qvel": (1 + nq, 1 + nq + nv, QVEL_TOL)}
    blocks["act"] = (1 + nq + nv, 1 + nq + nv + model.na, ACT_TOL)
    for name, (lo, hi, tol) in blocks.items():
        error = np.abs(warp_state[:, lo:hi] - cpu_state[:, lo:hi]).max()
        assert error < tol, f"{name} differs by {error:.3g} > {tol}"
    np.testing.assert_allclose(warp_state[:, 0], cpu_state[:, 0], rtol=0, atol=1e-12)
    for i in range(model.nsensor):
        adr, dim = model.sensor_adr[i], model.sensor_dim[i]
        cpu = cpu_sensors[:, adr : adr + dim]
        error = np.abs(warp_sensors[:, adr : adr + dim] - cpu).max()
        assert error < SENSOR_REL_TOL * np.abs(cpu).max(), model.sensor(i).name


@pytest.mark.needs_warp
@pytest.mark.slow
def test_batch_matches_cpu_mujoco_per_world(nao) -> None:
    model, state, control = nao
    other = variant(model, tendon_stiffness=0.5, actuator_gainprm=1.5)
    out = rollout_warp([model, other], state, control, RECORD_EVERY, device="cpu")
    nrec = NSTEP // RECORD_EVERY
    assert out.state.shape == (2, nrec, state.size)
    assert out.sensordata.shape == (2, nrec, model.nsensordata)
    assert out.batched_fields == ("actuator_gainprm", "tendon_stiffness")
    np.testing.assert_array_equal(out.valid_rows, [nrec, nrec])
    for world, item in enumerate((model, other)):
        assert_close_to_cpu(
            item, out.state[world], out.sensordata[world], *cpu_rows(item, state, control)
        )
    apart = np.abs(out.state[0, :, 1 : 1 + model.nq] - out.state[1, :, 1 : 1 + model.nq]).max()
    assert apart > 1000 * QPOS_TOL


@pytest.mark.needs_warp
@pytest.mark.slow
def test_diverged_world_is_flagged_not_reset_and_alone(nao) -> None:
    model, state, wave = nao
    hold = np.zeros_like(wave)  # the zero pose's setpoints: stand still
    unstable = variant(model, tendon_stiffness=-1000.0)  # gear springs pushing outwards
    out = rollout_warp([model, unstable], state, hold, RECORD_EVERY, device="cpu")
    nrec = NSTEP // RECORD_EVERY
    np.testing.assert_array_equal(out.diverged, [False, True])
    assert out.valid_rows[0] == nrec
    finite = np.isfinite(out.state[1]).all(axis=1)
    first_nan = int(np.argmin(finite))
    assert out.valid_rows[1] <= first_nan < nrec
    assert not finite[first_nan:].any()  # NaN stays NaN: no reset to qpos0
    assert_close_to_cpu(model, out.state[0], out.sensordata[0], *cpu_rows(model, state, hold))


@pytest.mark.needs_warp
def test_unsupported_model_names_feature_and_cpu_backend(nao) -> None:
    _, _, control = nao
    ideal = make_nao("G", None, seed=0)  # without M the joints are driven by `pid` servos
    state = np.empty(mujoco.mj_stateSize(ideal.model, FULL))
    mujoco.mj_getState(ideal.model, ideal.data, state, FULL)
    with pytest.raises(ParameterError, match=r"mjDYN_PID.*on the CPU \(the fit's backend 'local'"):
        rollout_warp([ideal.model], state, control[:, : ideal.model.nu], device="cpu")


@pytest.mark.needs_warp
@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (
            lambda s, c: (s[:-1], c),
            r"initial_state must .* shape \(71,\) or \(\d+, 71\), got shape \(70,\)",
        ),
        (lambda s, c: (s, c[:, :-1]), r"control must have shape \(nstep, nu=11\) or .*\(300, 10\)"),
        (lambda s, c: (s, c[:0]), r"nstep >= 1"),
        (lambda s, c: (s, np.where(c == c[0, 0], np.nan, c)), r"control must be finite"),
    ],
)
def test_bad_shapes_are_named(nao, edit, message) -> None:
    model, state, control = nao
    bad_state, bad_control = edit(state, control)
    with pytest.raises(ParameterError, match=message):
        rollout_warp([model], bad_state, bad_control, device="cpu")


@pytest.mark.needs_warp
@pytest.mark.parametrize("every", [0, NSTEP + 1, 1.5])
def test_bad_record_every(nao, every) -> None:
    model, state, control = nao
    with pytest.raises(ParameterError, match=r"record_every must be an integer in \[1, nstep"):
        rollout_warp([model], state, control, every, device="cpu")


@pytest.mark.needs_warp
def test_models_differing_in_unbatchable_field(nao) -> None:
    model, state, control = nao
    other = copy.deepcopy(model)
    other.opt.iterations += 1
    with pytest.raises(ParameterError, match=r"differ in 'opt.iterations'.*per-world fields"):
        rollout_warp([model, other], state, control, device="cpu")


@pytest.mark.needs_warp
def test_models_differing_in_zero_pattern(nao) -> None:
    model, state, control = nao
    other = copy.deepcopy(model)
    other.tendon_stiffness[0] = 0.0
    with pytest.raises(ParameterError, match=r"which entries of 'tendon_stiffness' are zero"):
        rollout_warp([model, other], state, control, device="cpu")


@pytest.mark.needs_warp
def test_models_of_different_mjcf(nao) -> None:
    model, state, control = nao
    other = make_nao("M,I,G,F,S", None, seed=0).model
    with pytest.raises(ParameterError, match=r"models\[1\] differs .* in the size of"):
        rollout_warp([model, other], state, control, device="cpu")


@pytest.mark.needs_warp
def test_unknown_device(nao) -> None:
    model, state, control = nao
    with pytest.raises(ParameterError, match=r"unknown Warp device 'tpu:0'; available: \["):
        rollout_warp([model], state, control, device="tpu:0")


@pytest.mark.needs_warp
def test_no_models(nao) -> None:
    _, state, control = nao
    with pytest.raises(ParameterError, match=r"non-empty sequence of mujoco\.MjModel"):
        rollout_warp([], state, control)


def test_missing_package_says_how_to_install(nao, monkeypatch) -> None:
    model, state, control = nao
    monkeypatch.setitem(sys.modules, "mujoco_warp", None)  # makes `import mujoco_warp` fail
    with pytest.raises(ModuleNotFoundError, match=r"pip install 'zmpkit\[gpu\]'"):
        rollout_warp([model], state, control)


@pytest.mark.needs_warp
@pytest.mark.slow
def test_warp_backend_costs_follow_the_cpu_batch(tmp_path) -> None:
    """The fit's ``"warp"`` backend on a recorded walk: float32 physics, the same verdicts.

    Measured on this walk: the cost totals of walking candidates differ by 4e-4 of their
    value (the ZMP and spectrum terms; encoders agree exactly after quantisation) and a
    falling candidate falls at the same frame; the tolerance is 1 % of the total.
    """
    from helpers.simfit_data import record_walk, small_case
    from zmpkit.simfit.backends import make_evaluator
    from zmpkit.simfit.experiments import read_experiments
    from zmpkit.simfit.problem import FitProblem

    params, doc, truth = small_case()
    experiments = tuple(read_experiments([record_walk(tmp_path)], get_robot("nao")))
    problem = FitProblem(get_robot("nao"), "M,G,S", params, doc, experiments)
    candidates = [[p.nominal for p in params], list(truth), [0.36, 310.0]]
    cpu = make_evaluator(problem, "local").costs(candidates)
    warp = make_evaluator(problem, "warp").costs(candidates)
    for (c,), (w,) in zip(cpu, warp, strict=True):
        assert w.completed == c.completed
        if c.completed == 1.0:
            total = c.total(problem.weights)
            assert abs(w.total(problem.weights) - total) <= 0.01 * total
    assert cpu[2][0].completed < 1.0  # the third candidate falls, on both


# The step loop: steps per launch, recorded rows and arrays, and the cache between calls.
# Each compares MuJoCo Warp with itself, so the results must be equal bit for bit.

ALL = ("state", "qpos", "qvel", "act", "sensordata", "site_xpos", "site_xmat")


def pair(model: mujoco.MjModel) -> list[mujoco.MjModel]:
    """Two candidates differing in two per-world fields (as a fit's generation does)."""
    return [model, variant(model, tendon_stiffness=0.5, actuator_gainprm=1.5)]


def assert_same_rollout(a, b) -> None:
    assert sorted(a.records) == sorted(b.records)
    for name in a.records:
        np.testing.assert_array_equal(a.records[name], b.records[name], err_msg=name)
    for name in ("steps", "time", "valid_rows", "solver_capped"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


@pytest.mark.needs_warp
def test_steps_per_launch_does_not_change_the_result(nao) -> None:
    model, state, control = nao
    short = control[:40]
    one = rollout_warp(pair(model), state, short, 3, "cpu", record=ALL, steps_per_launch=1)
    seven = rollout_warp(pair(model), state, short, 3, "cpu", record=ALL, steps_per_launch=7)
    assert_same_rollout(one, seven)  # 39 steps: 5 launches of 7 and one of 4 on CUDA


@pytest.mark.needs_warp
def test_recorded_rows_are_the_full_records_at_those_steps(nao) -> None:
    model, state, control = nao
    short = control[:40]
    full = rollout_warp(pair(model), state, short, 1, "cpu", record=ALL)
    wanted = [31, 5, 12, 12, 6]  # any order, duplicates dropped; steps past 31 not simulated
    some = rollout_warp(pair(model), state, short, device="cpu", record_steps=wanted, record=ALL)
    np.testing.assert_array_equal(some.steps, [5, 6, 12, 31])
    np.testing.assert_array_equal(full.steps, np.arange(1, 41))
    for name in ALL:
        np.testing.assert_array_equal(some.records[name], full.records[name][:, some.steps - 1])
    np.testing.assert_array_equal(some.time, full.time[:, some.steps - 1])
    np.testing.assert_array_equal(some.state[:, :, 0], some.time)


@pytest.mark.needs_warp
def test_only_the_arrays_asked_for_are_recorded(nao) -> None:
    model, state, control = nao
    out = rollout_warp([model], state, control[:6], device="cpu", record=("qpos", "site_xmat"))
    assert sorted(out.records) == ["qpos", "site_xmat"]
    assert out.records["qpos"].shape == (1, 6, model.nq)
    assert out.records["site_xmat"].shape == (1, 6, 9 * model.nsite)
    with pytest.raises(KeyError, match=r"'state' was not recorded; recorded: \['qpos'"):
        _ = out.state


@pytest.mark.needs_warp
def test_site_kinematics_lag_one_step_as_after_mj_step(nao) -> None:
    """A row's site pose is that of the previous row's qpos (MuJoCo's ``mj_step`` order)."""
    model, state, control = nao
    out = rollout_warp([model], state, control[:20], device="cpu", record=ALL)
    data = mujoco.MjData(model)
    for row in range(1, 20):
        data.qpos[:] = out.records["qpos"][0, row - 1]
        mujoco.mj_kinematics(model, data)
        xpos = out.records["site_xpos"][0, row].reshape(model.nsite, 3)
        xmat = out.records["site_xmat"][0, row].reshape(model.nsite, 9)
        # float32 kinematics against float64 ones of the same qpos: measured over the 300
        # steps, at most 7.5e-8 m in site_xpos and 2.9e-7 in site_xmat (QPOS_TOL: 34 x)
        np.testing.assert_allclose(xpos, data.site_xpos, rtol=0, atol=QPOS_TOL)
        np.testing.assert_allclose(xmat, data.site_xmat, rtol=0, atol=QPOS_TOL)


@pytest.mark.needs_warp
def test_a_second_call_reuses_the_warp_model_and_gives_the_same_result(nao) -> None:
    from zmpkit.sim import warp_batch, warp_session

    model, state, control = nao
    short = control[:30]
    warp_batch.clear_warp_cache()
    first = rollout_warp(pair(model), state, short, 2, "cpu", record=ALL)
    (session,) = warp_session._SESSIONS.values()
    again = rollout_warp(pair(model), state, short, 2, "cpu", record=ALL)
    assert list(warp_session._SESSIONS.values()) == [session]  # the same Warp model and data
    assert len(session.plans) == 1  # and the same buffers
    assert_same_rollout(first, again)
    # Other candidates of the same layout reuse it too, with their own per-world values...
    others = [variant(model, tendon_stiffness=2.0, actuator_gainprm=0.8), pair(model)[1]]
    reused = rollout_warp(others, state, short, 2, "cpu", record=ALL)
    assert list(warp_session._SESSIONS.values()) == [session]
    warp_batch.clear_warp_cache()
    fresh = rollout_warp(others, state, short, 2, "cpu", record=ALL)
    assert_same_rollout(reused, fresh)  # ...and nothing of the earlier calls stays in it
    # A shared field that changes (not per world in the cached model) builds a new one.
    (cached,) = warp_session._SESSIONS.values()
    heavier = [variant(m, body_mass=1.1) for m in others]
    rebuilt = rollout_warp(heavier, state, short, 2, "cpu", record=ALL)
    (session,) = warp_session._SESSIONS.values()  # in the place of the stale one
    assert session is not cached
    assert not np.array_equal(rebuilt.records["qpos"], fresh.records["qpos"])


@pytest.mark.needs_warp
def test_control_groups_run_as_separate_batches(nao) -> None:
    """Several control sequences (experiments) in one batch: each world as if alone."""
    model, state, wave = nao
    short = wave[:24]
    sequences = np.stack([short, 0.5 * short, -short])
    models = pair(model) + pair(model)  # candidate 0 and 1, in two experiments
    group = [2, 2, 1, 1]
    one = rollout_warp(
        models, state, sequences, device="cpu", record_steps=[3, 24], control_group=group
    )
    for worlds, sequence in (([0, 1], sequences[2]), ([2, 3], sequences[1])):
        alone = rollout_warp(pair(model), state, sequence, device="cpu", record_steps=[3, 24])
        for name in ("state", "sensordata"):
            np.testing.assert_array_equal(one.records[name][worlds], alone.records[name])
    per_item = rollout_warp(pair(model), state, sequences[:2], 4, "cpu")  # item i runs i
    np.testing.assert_array_equal(
        per_item.state[1], rollout_warp(pair(model), state, sequences[1], 4, "cpu").state[1]
    )


@pytest.mark.needs_warp
@pytest.mark.slow
def test_divergence_is_found_between_recorded_rows(nao) -> None:
    """Valid rows: those before the first failing step, recorded or not."""
    model, state, wave = nao
    hold = np.zeros_like(wave)
    unstable = variant(model, tendon_stiffness=-1000.0)
    full = rollout_warp([model, unstable], state, hold, 1, "cpu", record=("qpos",))
    first_bad_step = full.steps[full.valid_rows[1]]
    sparse = np.arange(10, NSTEP + 1, 10)
    some = rollout_warp(
        [model, unstable], state, hold, device="cpu", record_steps=sparse, record=("qpos",)
    )
    assert some.valid_rows[0] == len(sparse)
    assert some.valid_rows[1] == np.searchsorted(sparse, first_bad_step)
    assert some.diverged.tolist() == [False, True]


@pytest.mark.needs_warp
@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"record": ()}, r"record must name distinct arrays among \('state'"),
        ({"record": ("qpos", "qpos")}, r"record must name distinct arrays"),
        ({"record": ("xpos",)}, r"record must name distinct arrays"),
        ({"record_steps": []}, r"record_steps must be a non-empty 1-D set of integer steps"),
        ({"record_steps": [0, 3]}, r"in \[1, nstep=300\]"),
        ({"record_steps": [301]}, r"in \[1, nstep=300\]"),
        ({"record_steps": [1.5]}, r"integer steps"),
        ({"record_steps": [3], "record_every": 3}, r"give record_every or record_steps, not both"),
        ({"steps_per_launch": 0}, r"steps_per_launch must be an integer >= 1, got 0"),
        ({"steps_per_launch": 2.0}, r"steps_per_launch must be an integer >= 1, got 2.0"),
        ({"control_group": [0]}, r"control_group needs control of shape \(ngroup, nstep, nu\)"),
    ],
)
def test_bad_records_are_named(nao, options, message) -> None:
    model, state, control = nao
    with pytest.raises(ParameterError, match=message):
        rollout_warp([model], state, control, device="cpu", **options)


@pytest.mark.needs_warp
@pytest.mark.parametrize("group", [None, [0, 2], [0], [-1, 0], [0.0, 1.0]])
def test_bad_control_groups(nao, group) -> None:
    model, state, control = nao
    sequences = np.stack([control, control])
    with pytest.raises(ParameterError, match=r"control_group must give each of the 3 items"):
        rollout_warp(pair(model)[:1] * 3, state, sequences, device="cpu", control_group=group)


@pytest.mark.needs_warp
@pytest.mark.slow
def test_all_experiments_and_candidates_in_one_batch(tmp_path) -> None:
    """Two walks of different lengths x two candidates in one Warp batch: each experiment's
    signals are those of its own batch, bit for bit (worlds do not interact)."""
    import dataclasses

    from helpers.simfit_data import SEED, small_case
    from zmpkit.simfit.batched import simulate_batch
    from zmpkit.simfit.experiments import read_experiments
    from zmpkit.simfit.self_test import SelfTestPlan, record_experiments
    from zmpkit.simfit.warp_batched import simulate_batches_warp

    params, doc, truth = small_case()
    plan = SelfTestPlan(((0.2, 1.5), (0.1, 1.0)), ())
    paths, _ = record_experiments(get_robot("nao"), plan, doc, params, truth, "M,G", SEED, tmp_path)
    experiments = read_experiments(paths, get_robot("nao"))
    from zmpkit.simfit.problem import FitProblem

    problem = FitProblem(get_robot("nao"), "M,G,S", params, doc, tuple(experiments))
    truths = [problem.truth([p.nominal for p in params]), problem.truth(list(truth))]
    together = simulate_batches_warp(experiments, truths, "M,G,S", "cpu")
    assert len(together) == 2
    assert len(together[0][0].time_s) != len(together[1][0].time_s)  # different lengths
    for experiment, joint in zip(experiments, together, strict=True):
        alone = simulate_batch(experiment, truths, "M,G,S", warp_device="cpu")
        for a, b in zip(joint, alone, strict=True):
            assert len(a.time_s) > 0
            for f in dataclasses.fields(a):
                if f.init:  # the arrays; ``series`` is their one TimeSeries, not a field given
                    np.testing.assert_array_equal(getattr(a, f.name), getattr(b, f.name), f.name)


@pytest.mark.needs_warp
def test_chosen_columns_are_those_of_the_full_records(nao) -> None:
    model, state, control = nao
    records = ("qpos", "sensordata", "site_xpos", "site_xmat")
    full = rollout_warp(pair(model), state, control[:20], 4, "cpu", record=records)
    columns = {"qpos": [2], "sensordata": [5, 0, 1], "site_xpos": [1], "site_xmat": [1, 0]}
    some = rollout_warp(pair(model), state, control[:20], 4, "cpu", record=records, columns=columns)
    np.testing.assert_array_equal(some.records["qpos"], full.records["qpos"][:, :, [2]])
    np.testing.assert_array_equal(some.sensordata, full.sensordata[:, :, [5, 0, 1]])
    np.testing.assert_array_equal(some.records["site_xpos"], full.records["site_xpos"][:, :, 3:6])
    xmat = full.records["site_xmat"]
    np.testing.assert_array_equal(
        some.records["site_xmat"], np.concatenate([xmat[:, :, 9:18], xmat[:, :, 0:9]], axis=2)
    )
    assert some.square_error is None


@pytest.mark.needs_warp
def test_device_square_error_is_the_host_sum_of_the_same_rows(nao) -> None:
    """Two control groups, quantised and exact columns: the per-world sum accumulated on the
    device equals numpy's over the recorded qpos of the same rollout.

    Both widen the same float32 qpos to float64 and sum in float64; only the order of the
    additions differs, so they agree to float64 rounding (1e-12 relative; measured 0 on
    Warp's CPU device), far inside float32's 6e-8.
    """
    from zmpkit.sim.warp_batch import QposSquareError

    model, state, control = nao
    sequences = np.stack([control[:40], -control[:40]])
    columns, quantum = (7, 8, 12), (2e-5, 0.0, 2e-5)
    steps = (np.array([3, 10, 25, 40]), np.array([1, 2, 39]))
    rng = np.random.default_rng(0)
    targets = tuple(rng.normal(0.0, 0.02, (len(s), 3)) for s in steps)
    se = QposSquareError(columns, steps, targets, quantum)
    group = [0, 1, 1]
    out = rollout_warp(
        [*pair(model), model],
        state,
        sequences,
        device="cpu",
        record=("qpos",),
        control_group=group,
        square_error=se,
    )
    assert out.square_error is not None
    q = out.records["qpos"][:, :, list(columns)]
    step = np.array(quantum)
    q = np.where(step > 0, np.round(q / np.where(step > 0, step, 1.0)) * step, q)
    for world, g in enumerate(group):
        rows = steps[g] - 1
        host = np.sum((q[world, rows] - targets[g]) ** 2)
        assert host > 0.0
        np.testing.assert_allclose(out.square_error[world], host, rtol=1e-12, atol=0)
