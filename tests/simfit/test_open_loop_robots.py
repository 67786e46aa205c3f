"""Open-loop walk folders of robots other than the NAO: re-planned and replayed as they ran.

The OP3's servos are soft and P-only, so ``zmpkit walk`` pre-loads them: its targets are the
IK's plus the planned joint torques over the servo gain, and its pattern uses the OP3's own
foot separation, step limits and motion frame. A fit that re-planned the NAO's pattern
without the pre-load missed the recorded commands by 0.214 rad and refused the folder.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_dataset import SERIES_FILE, SUMMARY_FILE, write_series, write_summary
from zmpkit.experiments.walk_log import WALK_LOG_FILE, walk_log_from_record, write_walk_log
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.cost import experiment_cost
from zmpkit.simfit.experiments import read_experiments, read_walk_folder
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.shooting_window import ShootingWindow
from zmpkit.simfit.truth_doc import base_truth_path, load_robot_truth, load_truth_doc

OP3 = get_robot("op3")
SEED = 5


@pytest.fixture(scope="module")
def op3_open_walk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An open-loop OP3 walk written as ``zmpkit walk`` writes it (no figures, no report)."""
    config = WalkConfig(
        robot=OP3, duration_s=1.5, effects="M,G,S", seed=SEED, figures=False, controller="open"
    )
    trial = run_walk_trial(config)
    out = tmp_path_factory.mktemp("op3_open")
    write_summary(out / SUMMARY_FILE, trial.summary)
    write_series(
        out / SERIES_FILE, trial.pattern, trial.record, OP3.require_walking().series_joints
    )
    write_walk_log(out / WALK_LOG_FILE, walk_log_from_record(trial.record))
    return out


@pytest.mark.slow
def test_an_op3_open_loop_walk_is_replayed_with_the_commands_it_sent(op3_open_walk: Path):
    """Its recording's truth and noise seed bring the walk back exactly (7 CSV digits)."""
    experiment = read_walk_folder(op3_open_walk, OP3)
    assert experiment.closed_loop is None
    assert experiment.signals.joint_names == OP3.require_walking().series_joints
    truth = load_robot_truth(OP3, load_truth_doc(base_truth_path(OP3, None)))

    same = simulate_experiment(experiment, truth, "M,G,S", noise_seed=SEED)

    recorded = experiment.signals
    np.testing.assert_allclose(same.q_cmd_rad, recorded.q_cmd_rad, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(same.q_meas_rad, recorded.q_meas_rad, rtol=1e-6, atol=1e-9)
    assert experiment_cost(recorded, same).joint < 1e-5


@pytest.mark.slow
def test_a_walk_folder_of_a_robot_whose_fit_replays_steps_is_fitted_from_its_log(
    op3_open_walk: Path,
):
    """The OP3's fit replays steps; its ``zmpkit walk`` folder goes in by multiple shooting
    (it was refused: "a step dataset folder holds meta.json")."""
    assert OP3.require_fit().experiment == "step"
    windows = read_experiments([op3_open_walk], OP3, window_s=0.8, burn_in_s=0.2)
    assert windows
    assert all(isinstance(w, ShootingWindow) for w in windows)
    assert {w.source for w in windows} == {str(op3_open_walk / "walk_log.csv")}
