"""Compensation with feedback: tuned on several walks, judged on walks that differ from all of
them in speed, step duration and robot; a compensation that fells a standing walk is rejected."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.compensate.methods import CompensatedWalk
from zmpkit.compensate.summary import summary_of
from zmpkit.errors import ParameterError
from zmpkit.pipelines.walk_compensate import CompensateConfig, CompensateResult
from zmpkit.pipelines.walk_compensate_document import compensation_checks
from zmpkit.pipelines.walk_compensate_files import write_walk_compensate
from zmpkit.robots.registry import get_robot
from zmpkit.robots.truth_variant import scaled_truth_file


@pytest.mark.parametrize("quick", [True, False])
def test_validation_walks_differ_from_every_tuning_walk_in_what_matters(tmp_path, quick) -> None:
    config = CompensateConfig(method="half-sine", controller="zmpip", quick=quick)
    tuning = config.tuning_walks()
    validation = config.validation_walks(tmp_path)
    assert len({w.speed_mps for w in tuning}) >= 2
    assert len({w.step_duration_s for w in tuning}) >= 2
    assert all(w.truth is None and w.controller == "zmpip" for w in tuning)
    assert len(validation) == (2 if quick else 4)
    for v in validation:
        assert v.truth is not None
        for t in tuning:
            assert abs(v.speed_mps - t.speed_mps) > 1e-9
            assert abs(v.step_duration_s - t.step_duration_s) > 1e-9
            assert v.seed != t.seed


def test_open_loop_keeps_paper_b_validation_on_one_robot() -> None:
    config = CompensateConfig(method="half-sine", controller="open", quick=True)
    assert len(config.tuning_walks()) == 1
    assert all(w.truth is None for w in config.validation_walks())


def test_algorithm_2_runs_with_a_preview_controller_and_refuses_dcm_with_its_remedy() -> None:
    assert CompensateConfig(method="alg2", controller="zmpip").held_out
    with pytest.raises(ParameterError, match="run it with controller zmpip"):
        CompensateConfig(method="alg2", controller="dcm")


def test_a_held_out_robot_has_the_varied_value_and_nothing_else_changed(tmp_path) -> None:
    robot = get_robot("nao")
    path = scaled_truth_file(robot, "gear.stiffness", 1.3, tmp_path)
    shipped, varied = robot.truth.load(None), robot.truth.load(path)
    assert varied.gear.stiffness == pytest.approx(1.3 * shipped.gear.stiffness)
    assert dataclasses.replace(varied, gear=shipped.gear, source=shipped.source) == shipped
    with pytest.raises(ParameterError, match=r"no gear\.stifness"):
        scaled_truth_file(robot, "gear.stifness", 1.3, tmp_path)


def _walk(fell: bool, walk: WalkSpec) -> CompensatedWalk:
    t = np.arange(400) * 0.01
    zmp = np.zeros((t.size, 2))
    return CompensatedWalk(walk, 0.02, 0.01, fell, t, 0.01 * np.sin(t), (0.5, 3.5), zmp, zmp,
                           zmp, ())  # fmt: skip


def test_a_compensation_that_fells_a_standing_validation_walk_is_rejected(tmp_path) -> None:
    config = CompensateConfig(method="half-sine", controller="zmpip", quick=True)
    walks = config.validation_walks(tmp_path)
    baseline = (_walk(False, walks[0]), _walk(True, walks[1]))
    compensated = (_walk(True, walks[0]), _walk(True, walks[1]))
    summary = summary_of("half-sine", baseline, compensated)
    assert summary.walks_made_to_fall == 1
    assert summary.rejected
    assert summary.compensated_falls == 2
    assert summary.walks_compared == 0
    result = CompensateResult(config, summary, "half-sine", baseline, {"half-sine": compensated})
    write_walk_compensate(dataclasses.replace(result, config=dataclasses.replace(
        config, figures=False)), tmp_path)  # fmt: skip
    report = (tmp_path / "report.html").read_text()
    checks = {c.name: c for c in compensation_checks(result)}
    assert checks["makes no validation walk fall"].status == "missed"
    assert "1 walk(s) made to fall: rejected, do not use it" in report
    assert "gear.stiffness x1.3" in report
    kept = summary_of("half-sine", baseline, (_walk(False, walks[0]), _walk(True, walks[1])))
    assert not kept.rejected
