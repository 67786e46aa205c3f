"""Walks with a feedback controller re-simulated in closed loop; walks that fell, kept to the fall.

The independent implementation is ``zmpkit walk`` itself: a walk recorded by
:func:`~zmpkit.experiments.walk.run_walk_trial` with the controller must come back bit for
bit from the fit's rollout given the recorded noise seed and the recording's truth.
"""

from __future__ import annotations

import json
import shutil
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.closed_loop import NOISE_SEED_OFFSET
from zmpkit.simfit.cost import experiment_cost
from zmpkit.simfit.experiments import WalkExperiment, read_experiments, simulated_effects
from zmpkit.simfit.open_loop import is_open_loop
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import base_truth_path, load_robot_truth, load_truth_doc
from zmpkit.simfit.walk_plan import FALL_MARGIN_S

NAO = get_robot("nao")
SEED = 3


@pytest.fixture(scope="module")
def zmpip_walk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from helpers.simfit_data import record_feedback_walk

    return record_feedback_walk(tmp_path_factory.mktemp("zmpip_walk"), seed=SEED)


@pytest.fixture(scope="module")
def open_walk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from helpers.simfit_data import record_walk

    return record_walk(tmp_path_factory.mktemp("open_walk"))


def _shipped_truth():
    return load_robot_truth(NAO, load_truth_doc(base_truth_path(NAO, None)))


def _walk(folder: Path) -> WalkExperiment:
    (experiment,) = read_experiments([folder], NAO)
    assert isinstance(experiment, WalkExperiment)
    return experiment


@pytest.mark.slow
def test_a_zmpip_walk_reads_its_controller_and_settings(zmpip_walk: Path) -> None:
    experiment = _walk(zmpip_walk)
    settings = experiment.closed_loop
    assert settings is not None
    assert (settings.controller, settings.seed, settings.effects) == ("zmpip", SEED, "M,G,S")
    assert experiment.duration_s == pytest.approx(1.5)
    assert settings.duration_s == experiment.duration_s
    assert experiment.effects == "M,G,S"
    assert not is_open_loop(experiment)


@pytest.mark.slow
def test_the_closed_loop_rollout_reproduces_the_walk_bit_for_bit(zmpip_walk: Path) -> None:
    """The recording's truth and noise seed: the controller's walk comes back exactly."""
    experiment = _walk(zmpip_walk)
    same = simulate_experiment(experiment, _shipped_truth(), "M,G,S", noise_seed=SEED)
    rec = experiment.signals
    # the CSV keeps 7 significant digits
    np.testing.assert_allclose(same.q_meas_rad, rec.q_meas_rad, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(same.q_cmd_rad, rec.q_cmd_rad, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(same.trunk_tilt_rad, rec.trunk_tilt_rad, rtol=1e-6, atol=1e-9)
    assert experiment_cost(rec, same).joint < 1e-5


@pytest.mark.slow
def test_the_fit_reads_fresh_noise_so_its_truth_costs_the_noise_floor(zmpip_walk: Path) -> None:
    """The fit's own seed is the recorded one plus the offset: not the recorded realisation."""
    experiment = _walk(zmpip_walk)
    assert NOISE_SEED_OFFSET != 0
    fit = simulate_experiment(experiment, _shipped_truth(), "M,G,S")
    explicit = simulate_experiment(
        experiment, _shipped_truth(), "M,G,S", noise_seed=SEED + NOISE_SEED_OFFSET
    )
    np.testing.assert_array_equal(fit.q_meas_rad, explicit.q_meas_rad)
    assert experiment_cost(experiment.signals, fit).joint > 1e-3


@pytest.mark.slow
def test_an_open_loop_replay_of_a_zmpip_walk_would_not_reproduce_it(zmpip_walk: Path) -> None:
    """Why a feedback walk needs its controller: the commands differ from the plan's."""
    from zmpkit.simfit.walk_plan import match_walk_plan

    experiment = _walk(zmpip_walk)
    with pytest.raises(InputFileError, match="differs from the recorded command"):
        match_walk_plan(
            NAO,
            zmpip_walk,
            experiment.speed_mps,
            experiment.step_duration_s,
            experiment.signals,
        )


@pytest.mark.slow
def test_the_local_backend_routes_closed_loop_walks_and_matches_serial(
    zmpip_walk: Path, open_walk: Path
) -> None:
    from zmpkit.simfit.backends import make_evaluator
    from zmpkit.simfit.pool_backend import RoutedEvaluator

    experiments = tuple(read_experiments([zmpip_walk, open_walk], NAO))
    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(NAO, None))
    problem = FitProblem(NAO, "M,G,S", params, doc, experiments)
    candidates = [[0.7, 1200.0], [0.6, 900.0]]
    serial = make_evaluator(problem, "serial").costs(candidates)
    routed = make_evaluator(problem, "local", workers=1)
    try:
        assert isinstance(routed, RoutedEvaluator)
        assert routed.costs(candidates) == serial
    finally:
        routed.close()


def test_the_warp_backend_refuses_closed_loop_walks_in_one_line(
    zmpip_walk: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from zmpkit.simfit.backends import make_evaluator

    monkeypatch.setitem(sys.modules, "mujoco_warp", types.ModuleType("mujoco_warp"))
    experiments = tuple(read_experiments([zmpip_walk], NAO))
    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    problem = FitProblem(NAO, "M,G,S", params, {}, experiments)
    with pytest.raises(ParameterError, match=r"^backend 'warp' replays open-loop experiments "
                       r"only; .* use --backend local$"):  # fmt: skip
        make_evaluator(problem, "warp")


def _edit_summary(folder: Path, **changes: object) -> None:
    path = folder / "summary.json"
    summary = json.loads(path.read_text())
    summary.update(changes)
    path.write_text(json.dumps(summary))


def _cut_series(folder: Path, rows: int) -> None:
    path = folder / "timeseries.csv"
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[: 1 + rows]) + "\n")


@pytest.mark.parametrize("kind", ["zmpip", "open"])
@pytest.mark.slow
def test_a_fallen_walk_is_kept_up_to_the_margin_before_its_fall(
    kind: str, zmpip_walk: Path, open_walk: Path, tmp_path: Path
) -> None:
    """A recording cut after 3.0 s and marked fallen: kept to 0.5 s before, its plan re-found."""
    folder = tmp_path / kind
    shutil.copytree(zmpip_walk if kind == "zmpip" else open_walk, folder)
    whole = _walk(folder)
    cut = int(np.searchsorted(whole.signals.time_s, 3.0)) + 1  # rows up to 3.0 s
    _cut_series(folder, cut)
    _edit_summary(folder, fell=True, fall_time_s=3.0)
    fallen = _walk(folder)
    t = fallen.signals.time_s
    last = whole.signals.time_s[cut - 1]
    assert fallen.fall_time_s == 3.0
    assert t[-1] <= last - FALL_MARGIN_S + 1e-9
    assert t[-1] > last - FALL_MARGIN_S - 0.011  # one 10 ms frame
    n = t.size
    np.testing.assert_array_equal(fallen.signals.q_meas_rad, whole.signals.q_meas_rad[:n])
    simulated = simulate_experiment(fallen, _shipped_truth(), "M,G,S")
    assert simulated.time_s.size == n  # the rollout keeps the recorded rows only
    assert experiment_cost(fallen.signals, simulated).completed == 1.0
    if kind == "open":  # the thread-pool batch cuts its schedule at the same row
        from zmpkit.simfit.batched import simulate_batch

        (batched,) = simulate_batch(fallen, [_shipped_truth()], "M,G,S", nthread=1)
        np.testing.assert_array_equal(batched.q_meas_rad, simulated.q_meas_rad)
        np.testing.assert_array_equal(batched.trunk_tilt_rad, simulated.trunk_tilt_rad)


def test_a_walk_that_fell_at_once_says_there_is_nothing_to_fit(
    zmpip_walk: Path, tmp_path: Path
) -> None:
    folder = tmp_path / "walk"
    shutil.copytree(zmpip_walk, folder)
    _cut_series(folder, 40)
    _edit_summary(folder, fell=True, fall_time_s=0.39)
    with pytest.raises(InputFileError, match=r"the walk fell at 0\.39 s: .* nothing to fit"):
        read_experiments([folder], NAO)


def test_walk_folder_errors_of_a_feedback_walk(zmpip_walk: Path, tmp_path: Path) -> None:
    folder = tmp_path / "walk"
    shutil.copytree(zmpip_walk, folder)
    _edit_summary(folder, controller="mpc")
    with pytest.raises(InputFileError, match=r"controller 'mpc' is not one of zmpkit's"):
        read_experiments([folder], NAO)
    _edit_summary(folder, controller="zmpip", effects="M,Q")
    with pytest.raises(InputFileError, match=r"summary\.json, column 'effects': unknown effect"):
        read_experiments([folder], NAO)
    _edit_summary(folder, effects="M,G,S", commanded_speed_mps=0.15)
    with pytest.raises(
        InputFileError,
        match=r"column 'com_ref_x_m': the re-planned zmpip walk .* differs from the recorded plan",
    ):
        read_experiments([folder], NAO)


def test_simulated_effects_add_what_the_walks_ran(zmpip_walk: Path) -> None:
    experiments = read_experiments([zmpip_walk], NAO)
    assert simulated_effects("M,S", experiments) == "M,G,S"
    assert simulated_effects("M,I,G,F,S", experiments) == "all"
    assert simulated_effects("M,G", []) == "M,G"


@pytest.mark.slow
def test_identify_sim_fits_a_zmpip_walk_with_no_flag_and_states_its_verdict(
    zmpip_walk: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The default walk, fitted with the default backend: intervals and a verdict written."""
    import yaml

    from zmpkit.cli.app import main

    out = tmp_path / "fit"
    argv = ["identify", "sim", str(zmpip_walk), "--robot", "nao", "--quick"]
    code = main([*argv, "--generations", "2", "--out", str(out), "--report", "md"])
    assert code == 0
    printed = capsys.readouterr().out
    assert "the model explains the data" in printed or "does not explain" in printed
    doc = yaml.safe_load((out / "fitted_parameters.yaml").read_text())
    assert doc["effects"] == "M,G,S"
    assert set(doc["adequacy"]) >= {"explains_data", "noise_floor", "best_cost", "verdict"}
    for entry in doc["parameters"].values():
        assert "interval_95" in entry
        assert "resolution_is_precision" in entry
    assert "the model explains the data" in (out / "report.md").read_text()
