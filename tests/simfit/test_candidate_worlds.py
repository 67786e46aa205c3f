"""Candidates written into one compiled model against each candidate's own compiled MJCF.

The fit's parameters of every effect the catalogues have (NAO and TEO: M, I, G, F, S, C;
OP3: M, I, G, F) are drawn at random in their bounds (hypothesis); every numeric field of each
candidate's world (the template with its per-world fields, derived ones included) must equal
the field of the model compiled from that candidate's own MJCF, bit for bit, and the
simulations on it must read what the compiled ones read, bit for bit. The Warp test
(``needs_warp``, skipped without ``mujoco_warp``) runs a generation both ways on Warp's CPU
device: the same costs.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from helpers.simfit_data import record_walk
from helpers.warp_reference import model_arrays
from zmpkit.errors import ParameterError, SimulationDivergedError
from zmpkit.robots.fit_parameter import FitParameter, fit_parameter
from zmpkit.robots.registry import get_robot
from zmpkit.robots.robot import Robot
from zmpkit.sim.posed import PosedData, PosedSimulation
from zmpkit.sim.world import Simulation
from zmpkit.simfit.candidate_worlds import (
    CandidateValues,
    CandidateWorlds,
    candidate_worlds,
    field_map_gap,
)
from zmpkit.simfit.experiments import StepExperiment, WalkExperiment, read_experiments
from zmpkit.simfit.open_loop import _pose, posed_simulations, posed_world_simulations
from zmpkit.simfit.parameters import robot_catalogue
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

NAO = get_robot("nao")
TEO = get_robot("teo")
EFFECTS = ("M,I,G,F,S", "M,G,S", "G,F", "M,I", "none")
"""Effect sets the fields are checked under (a rule writes only what the MJCF has)."""


def _op3() -> Robot | None:
    from zmpkit.robots.op3.preset import op3_missing_reason

    return None if op3_missing_reason() else get_robot("op3")


OP3 = _op3()
"""The OP3, where its model (an optional wheel) is installed."""


EXTRA = {
    "nao": (
        fit_parameter("M", "pid_p_volts", "pid_volts.p", 1277.9, (300.0, 5000.0), "V/rad"),
        fit_parameter("M", "pid_i_volts", "pid_volts.i", 14.186, (1.0, 100.0), "V/(rad·s)"),
        fit_parameter("F", "flex_damping", "flex[*].damping", 0.5, (0.05, 5.0), "N·m·s/rad"),
    ),
    "teo": (
        fit_parameter("M", "pid_ki", "pid.ki_link", 90000.0, (9000.0, 900000.0), "N·m/(rad·s)"),
        fit_parameter("G", "gear_backlash", "gear.backlash", 3e-4, (3e-5, 3e-3), "rad"),
        fit_parameter("F", "flex_damping", "flex[*].damping", 40.0, (4.0, 400.0), "N·m·s/rad"),
    ),
    "op3": (
        fit_parameter("M", "pid_i_gain", "pid.ki", 1.0, (0.1, 10.0), "N·m/(rad·s)"),
        fit_parameter("M", "pid_d_gain", "pid.kd", 0.1, (0.01, 1.0), "N·m·s/rad"),
        fit_parameter("F", "flex_damping", "flex[0,1].damping", 0.2, (0.02, 2.0), "N·m·s/rad"),
    ),
}
"""Numbers the robots' rules map beyond their catalogues (a user's catalogue may fit them)."""


def _parameters(robot: Robot) -> tuple[FitParameter, ...]:
    return (*robot_catalogue(robot), *EXTRA[robot.name])


def _candidates(robot: Robot, units: Sequence[Sequence[float]]) -> CandidateValues:
    """Candidates of ``robot``'s whole catalogue (and :data:`EXTRA`) at the normalised
    ``units`` (as many as given, the catalogue's first)."""
    params = _parameters(robot)[: len(units[0])]
    values = np.array([[p.from_unit(u) for p, u in zip(params, row, strict=True)] for row in units])
    doc = load_truth_doc(base_truth_path(robot, None))
    return CandidateValues(robot, params, doc, values)


def _units(
    nparam: int, low: float = 0.0, high: float = 1.0
) -> st.SearchStrategy[list[list[float]]]:
    unit = st.floats(low, high, allow_nan=False)
    return st.lists(st.lists(unit, min_size=nparam, max_size=nparam), min_size=1, max_size=3)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_each_nao_world_is_the_candidates_compiled_model(data: st.DataObject) -> None:
    _check_worlds(NAO, data)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_each_teo_world_is_the_candidates_compiled_model(data: st.DataObject) -> None:
    """Softening springs (their stage tendons) and a payload body (its position)."""
    _check_worlds(TEO, data)


@pytest.mark.slow
@pytest.mark.skipif(OP3 is None, reason="the OP3's model is not installed (zmpkit[robots])")
@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_each_op3_world_is_the_candidates_compiled_model(data: st.DataObject) -> None:
    assert OP3 is not None
    _check_worlds(OP3, data)


def _check_worlds(robot: Robot, data: st.DataObject) -> None:
    """Every field of each candidate's world equals its compiled model's, bit for bit."""
    units = data.draw(_units(len(_parameters(robot))), label="units")
    effects = data.draw(st.sampled_from(EFFECTS), label="effects")
    candidates = _candidates(robot, units)
    worlds = candidate_worlds(candidates, effects)
    for c in range(len(candidates)):
        compiled = mujoco.MjModel.from_xml_string(
            robot.description(effects, candidates.truth(c)).mjcf
        )
        want, got = model_arrays(compiled), model_arrays(worlds.fields.model(c))
        assert want.keys() == got.keys()
        for name, value in want.items():
            np.testing.assert_array_equal(got[name], value, err_msg=f"{name}, candidate {c}")
        description = robot.description(effects, candidates.truth(c))
        mine = worlds.description_of(c)
        for foot in description.feet:
            assert mine.ft_offset(foot.foot) == description.ft_offset(foot.foot)


def _run(sim: Simulation, walk: WalkExperiment) -> list[np.ndarray] | str:
    """The readings 40 steps after the walk's start pose (8 F-T samples), or why it diverged."""
    _pose(walk, sim)
    try:
        sim.step(40)
    except SimulationDivergedError as exc:
        return str(exc)
    feet = [f.foot for f in sim.robot.feet]
    return [sim.data.qpos.copy(), sim.encoders(), *(sim.ft(f) for f in feet), *sim.imu()]


@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> WalkExperiment:
    (experiment,) = read_experiments([record_walk(tmp_path_factory.mktemp("worlds_walk"))], NAO)
    assert isinstance(experiment, WalkExperiment)
    return experiment


@settings(max_examples=4, deadline=None)
@given(units=_units(len(robot_catalogue(NAO))))
@example(units=[[p.to_unit(p.nominal) for p in robot_catalogue(NAO)]])  # walks: readings
@pytest.mark.slow
def test_simulations_on_the_worlds_read_as_the_compiled_ones(
    walk: WalkExperiment, units: list[list[float]]
) -> None:
    """S on: each candidate's F-T offsets, noise and filter on the host, from the pose on.

    A candidate that diverges must diverge alike (same time, joint and reason): about
    half of the catalogue's random candidates diverge within 20 ms of the pose (serial path
    alike); the nominal one (an explicit example) walks.
    """
    candidates = _candidates(NAO, units)
    worlds = candidate_worlds(candidates, "M,I,G,F,S")
    host = worlds.fields.model(0)
    for c in range(len(candidates)):
        worlds.fields.write_into(host, c)
        got = _run(Simulation(worlds.description_of(c), seed=0, model=host), walk)
        want = _run(NAO.make_simulation("M,I,G,F,S", candidates.truth(c), seed=0), walk)
        if isinstance(want, str) or isinstance(got, str):
            assert got == want
            continue
        for mine, theirs in zip(got, want, strict=True):
            np.testing.assert_array_equal(mine, theirs)


def _posed_state(sim: Simulation | PosedSimulation) -> list[np.ndarray]:
    """The posed state, readings and sensor-channel states, as a batch reads them."""
    feet = [f.foot for f in sim.robot.feet]
    data = PosedData.of(sim.model, sim.data) if isinstance(sim, Simulation) else sim.data
    arrays = [data.state, data.qpos, data.sensordata, data.site_xpos, data.site_xmat]
    channels = [sim.ft_channel(f) for f in feet]
    return [*arrays, *(c.output for c in channels), *(c._state for c in channels)]


def test_posed_worlds_are_the_posed_simulations(walk: WalkExperiment) -> None:
    """Two experiments (the second restarts the same simulation), S on (the F-T filter)."""
    candidates = _candidates(NAO, [[0.2] * 13, [0.8] * 13, [0.5] * 13])
    worlds = candidate_worlds(candidates, "M,I,G,F,S")
    mine = posed_world_simulations([walk, walk], worlds)
    theirs = posed_simulations([walk, walk], candidates.truths(), "M,I,G,F,S")
    for got_e, want_e in zip(mine, theirs, strict=True):
        for a, b in zip(got_e, want_e, strict=True):
            assert a.data.time == b.data.time
            assert a.servo.position == b.servo.position
            assert a.servo.velocity == b.servo.velocity
            np.testing.assert_array_equal(a.encoders_of(a.data.qpos), b.encoders())
            for got, want in zip(_posed_state(a), _posed_state(b), strict=True):
                np.testing.assert_array_equal(got, want)


def test_a_robot_or_a_parameter_without_a_map_says_why() -> None:
    assert NAO.fit is not None
    unmapped = dataclasses.replace(NAO, fit=dataclasses.replace(NAO.fit, fields=None))
    gap = field_map_gap(unmapped, robot_catalogue(NAO))
    assert gap == "NAO has no map from its fit parameters to model fields"
    inertia = fit_parameter("G", "gear_inertia", "gear.inertia_link", 1e-3, (1e-4, 1e-2), "kg·m²")
    gap = field_map_gap(NAO, (*robot_catalogue(NAO), inertia))
    assert gap == "NAO's field map does not cover the parameters ['gear_inertia']"
    assert field_map_gap(NAO, robot_catalogue(NAO)) is None


def test_a_softening_flex_spring_is_not_mapped() -> None:
    candidates = _candidates(NAO, [[0.5] * 13])
    doc = dict(candidates.base_doc)
    doc["flex"] = [
        {**e, "softening_torque": 1.0, "stiffness": [e["stiffness"][0], 0, 0]} for e in doc["flex"]
    ]
    softening = CandidateValues(NAO, candidates.parameters, doc, candidates.values)
    with pytest.raises(ParameterError, match="softening flex spring"):
        candidate_worlds(softening, "M,G,F")


def test_without_fitted_masses_nothing_is_derived() -> None:
    params = tuple(p for p in robot_catalogue(NAO) if p.effect != "C")
    doc = load_truth_doc(base_truth_path(NAO, None))
    values = np.array([[p.nominal for p in params]] * 2)
    worlds: CandidateWorlds = candidate_worlds(CandidateValues(NAO, params, doc, values), "M,G")
    assert "body_mass" in worlds.fields.values
    assert "dof_invweight0" not in worlds.fields.values


def test_truth_objects_take_the_compile_path(walk: WalkExperiment) -> None:
    from zmpkit.simfit.warp_batched import field_path_gap

    candidates = _candidates(NAO, [[0.5] * 13])
    assert field_path_gap([walk], candidates) is None
    assert field_path_gap([walk], candidates.truths()) == (
        "the candidates come as truth objects, not as parameter values"
    )


@pytest.mark.needs_warp
@pytest.mark.slow
def test_warp_costs_of_the_fields_are_those_of_the_compiled_models(walk: WalkExperiment) -> None:
    """Warp's CPU device, every effect and the whole catalogue (C: derived fields too).

    The per-world values are the compiled models' (tested above) and the template is the
    first candidate's compiled model either way, so the float32 rollouts, hence the costs,
    are the same, bit for bit: the nominal candidate, two around it, and a soft and heavy
    one.
    """
    from zmpkit.simfit.cost import CostWeights
    from zmpkit.simfit.warp_batched import costs_batches_warp, simulate_batches_warp

    nominal = [p.to_unit(p.nominal) for p in robot_catalogue(NAO)]
    soft = [0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0]  # soft, heavy
    candidates = _candidates(NAO, [nominal, [0.45] * 13, [0.55] * 13, soft])
    effects = "M,I,G,F,S"
    fields = costs_batches_warp([walk], candidates, effects, "cpu", True)
    compiled = costs_batches_warp([walk], candidates.truths(), effects, "cpu", True)
    assert fields == compiled
    completed = [terms.completed for terms in fields[0]]
    assert completed[0] == 1.0, completed  # the nominal walks
    totals = {terms.total(CostWeights()) for terms in fields[0]}
    assert len(totals) == len(candidates)  # four different rollouts
    signals = simulate_batches_warp([walk], candidates, effects, "cpu")
    serial = simulate_batches_warp([walk], candidates.truths(), effects, "cpu")
    for got, want in zip(signals[0], serial[0], strict=True):
        for name in ("time_s", "q_meas_rad", "zmp_m", "force_z_n", "trunk_tilt_rad"):
            np.testing.assert_array_equal(getattr(got, name), getattr(want, name))


@pytest.fixture(scope="module")
def teo_step(tmp_path_factory: pytest.TempPathFactory) -> StepExperiment:
    from zmpkit.experiments import StepExperimentConfig, run_step_sweep

    config = StepExperimentConfig(
        TEO, targets_m=(0.04,), effects="M,G,F,S", settle_s=1.0, hold_s=0.5
    )
    dataset = run_step_sweep(config, tmp_path_factory.mktemp("worlds_teo_step"), workers=1)
    (experiment,) = read_experiments([Path(dataset.path)], TEO)
    assert isinstance(experiment, StepExperiment)
    return experiment


@pytest.mark.needs_warp
@pytest.mark.slow
def test_warp_costs_of_teo_fields_are_those_of_its_compiled_models(
    teo_step: StepExperiment,
) -> None:
    """TEO's step on Warp's CPU device: softening springs' stage tendons and the payload's
    position per world; the same costs as the compiled models', bit for bit."""
    from zmpkit.simfit.cost import CostWeights
    from zmpkit.simfit.warp_batched import costs_batches_warp

    nominal = [p.to_unit(p.nominal) for p in robot_catalogue(TEO)]
    candidates = _candidates(TEO, [nominal, [0.4] * 13, [0.6] * 13])
    effects = "M,I,G,F,S"
    fields = costs_batches_warp([teo_step], candidates, effects, "cpu", True)
    compiled = costs_batches_warp([teo_step], candidates.truths(), effects, "cpu", True)
    assert fields == compiled
    assert len({terms.total(CostWeights()) for terms in fields[0]}) == len(candidates)
