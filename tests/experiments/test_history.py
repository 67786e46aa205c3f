"""Trial-to-trial variability of the virtual TEO: stance, previous lean, per-sensor gains."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from zmpkit.errors import InputFileError
from zmpkit.experiments import StepExperimentConfig, run_step_trial
from zmpkit.experiments.history import previous_target, stance_offsets
from zmpkit.robots.registry import get_robot
from zmpkit.robots.teo import teo_robot
from zmpkit.robots.teo.truth import DEFAULT_TRUTH_PATH, truth_from_doc
from zmpkit.robots.teo.truth_variants import truth_variant
from zmpkit.sim.sensor_errors import TrialVariability


def test_previous_target_is_the_one_before_in_increasing_order() -> None:
    targets = (0.04, 0.0, 0.02, 0.1)
    assert previous_target(targets, 0.0) is None
    assert previous_target(targets, 0.04) == 0.02
    assert previous_target(targets, 0.1) == 0.04


def test_stance_offsets_only_on_leaning_joints_seeded_and_off_by_default() -> None:
    joints = ("a", "b", "c")
    assert not np.any(stance_offsets(TrialVariability(), joints, ("a", "c"), 3))
    on = TrialVariability(stance_std_rad=0.002)
    first = stance_offsets(on, joints, ("a", "c"), 3)
    assert first[1] == 0.0
    assert np.all(first[[0, 2]] != 0.0)
    np.testing.assert_array_equal(first, stance_offsets(on, joints, ("a", "c"), 3))
    assert not np.array_equal(first, stance_offsets(on, joints, ("a", "c"), 4))


def test_truth_gives_per_sensor_per_axis_gains_and_variability() -> None:
    doc = truth_variant("variability")
    truth = truth_from_doc(doc)
    threshold = get_robot("teo").contact_force_threshold_n
    robot = teo_robot("all", truth, threshold)
    assert robot.ft_gain_error("right") == tuple(doc["sensors"]["ft_gain_error"]["right"])
    assert robot.ft_gain_error("left") != robot.ft_gain_error("right")
    assert robot.variability.sequence
    assert robot.variability.stance_std_rad > 0.0
    shipped = teo_robot("all", None, threshold)
    assert shipped.variability == TrialVariability()
    assert shipped.ft_gain_error("right") == (shipped.sensor_params.ft_gain_error,) * 6


def test_a_malformed_per_sensor_gain_names_the_field() -> None:
    doc = yaml.safe_load(DEFAULT_TRUTH_PATH.read_text(encoding="utf-8"))
    doc["sensors"]["ft_gain_error"] = {"right": [0.01, 0.02]}
    with pytest.raises(InputFileError, match=r"sensors.ft_gain_error per sensor must be"):
        truth_from_doc(doc, "bad.yaml")


@pytest.mark.slow
def test_the_previous_lean_leaves_the_robot_elsewhere(tmp_path) -> None:
    """Hysteresis: after the lean to 0.08 m and back, the upright robot stands differently."""
    doc = yaml.safe_load(DEFAULT_TRUTH_PATH.read_text(encoding="utf-8"))
    doc["variability"] = {"sequence": True, "previous_hold_s": 3.0}
    path = tmp_path / "truth.yaml"
    path.write_text(yaml.safe_dump(doc))
    targets = (0.0, 0.08, 0.1)
    fresh = StepExperimentConfig(get_robot("teo"), targets_m=targets, plane="frontal", hold_s=0.5)
    carried = StepExperimentConfig(
        get_robot("teo"), targets_m=targets, plane="frontal", hold_s=0.5, truth=str(path)
    )
    a, b = run_step_trial(fresh, 0.1), run_step_trial(carried, 0.1)
    assert b.t_step_s == pytest.approx(a.t_step_s + 6.0)  # the previous lean, there and back
    before_a = a.time < a.t_step_s
    before_b = b.time < b.t_step_s
    torque_a = a.left_wrench[before_a, 3].mean() + a.right_wrench[before_a, 3].mean()
    torque_b = b.left_wrench[before_b, 3].mean() + b.right_wrench[before_b, 3].mean()
    # the standing moment the lean left, against the noise of the two means (Tx noise
    # 0.02 N·m per sample, two sensors, low-passed samples counted as independent: generous)
    noise = 0.02 * np.sqrt(2.0 / np.count_nonzero(before_a) + 2.0 / np.count_nonzero(before_b))
    assert abs(torque_b - torque_a) > 5.0 * noise
    first = run_step_trial(carried, 0.0)  # the first target has no previous lean
    assert first.t_step_s == pytest.approx(a.t_step_s)
