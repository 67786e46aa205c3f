"""A robot is a value: resolved once at the boundary, passed down, recorded by its source.

Below the pipelines every config and function takes a :class:`~zmpkit.robots.robot.Robot`;
it crosses into a worker process as its ``source`` and comes back as the same robot; the
files a run writes name it by that source, exactly as they named it when robots travelled
as names (so earlier datasets and caches resume).
"""

from __future__ import annotations

import copy
import hashlib
import json
import pickle
from pathlib import Path

import pytest

from helpers.biped import write_biped_robot
from zmpkit.compensate.evaluations import Evaluation, WalkSpec, _key, _to_json
from zmpkit.experiments import StepExperimentConfig
from zmpkit.experiments.sweep import new_meta
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.robots.op3 import preset
from zmpkit.robots.registry import get_robot
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N


@pytest.mark.parametrize("name", ["teo", "nao"])
def test_a_built_in_robot_pickles_as_its_name_and_comes_back_the_same(name: str) -> None:
    robot = get_robot(name)
    data = pickle.dumps(robot)
    assert len(data) < 200  # the reference, not the model
    assert pickle.loads(data) is robot
    assert copy.deepcopy(robot) is robot


def test_a_robot_file_pickles_as_its_absolute_path(tmp_path: Path) -> None:
    robot = get_robot(write_biped_robot(tmp_path))
    assert Path(robot.source).is_absolute()
    assert pickle.loads(pickle.dumps(robot)) is robot


def test_a_config_crosses_to_a_worker_with_its_robot() -> None:
    config = WalkConfig(get_robot("nao"), duration_s=2.0, effects="none")
    again = pickle.loads(pickle.dumps(config))
    assert again.robot is config.robot
    assert again == config


def test_a_step_sweep_records_its_robot_by_source() -> None:
    config = StepExperimentConfig(get_robot("teo"), targets_m=(0.0, 0.02))
    settings = config.settings()
    assert settings["robot"] == "teo"
    assert json.loads(json.dumps(settings)) == settings  # JSON-ready, nothing of the robot


def test_a_robot_without_a_balance_model_is_refused_by_the_step_config() -> None:
    with pytest.raises(ValueError, match=r"^robot 'nao' has no balance model"):
        StepExperimentConfig(get_robot("nao"))


@pytest.mark.slow
def test_the_op3_balance_dataset_records_the_op3s_own_threshold() -> None:
    """OP3 weighs about 31 N: 10 N, the default, would call a foot in contact at a third."""
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    op3 = get_robot("op3")
    meta = new_meta(StepExperimentConfig(op3, targets_m=(0.0,)))
    assert meta["robot"] == "op3"
    assert meta["contact_threshold_n"] == op3.contact_force_threshold_n
    weight_n = op3.require_balance().mass_kg * 9.81
    assert meta["contact_threshold_n"] == pytest.approx(0.05 * weight_n, rel=0.01)
    assert meta["contact_threshold_n"] < CONTACT_FORCE_THRESHOLD_N


def test_a_cached_walk_is_found_under_the_key_it_had_when_robots_were_names() -> None:
    walk = WalkSpec(speed_mps=0.2, seed=1, duration_s=3.0, robot=get_robot("nao"))
    by_name = {
        "speed_mps": 0.2, "seed": 1, "duration_s": 3.0, "effects": "all", "robot": "nao",
        "step_duration_s": 0.5, "controller": "open", "truth": None, "truth_label": "",
    }  # fmt: skip
    assert walk.as_dict() == by_name
    assert list(walk.as_dict()) == list(by_name)  # the cache files' field order
    text = json.dumps({"walk": by_name, "offset": None}, sort_keys=True)
    assert _key(walk, None) == hashlib.sha1(text.encode()).hexdigest()[:20]
    cached = json.loads(_to_json(Evaluation(walk, None, 0.01, 0.02, 2.0, 0.01, False)))
    assert cached["walk"] == by_name
