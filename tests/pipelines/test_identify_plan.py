"""identify plan on the NAO: the plan's judgement equals the fit's own, and it writes protocols."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
import yaml

from zmpkit.experiments.double_support import double_support_targets
from zmpkit.pipelines.identify_plan import IdentifyPlanConfig, run_identify_plan
from zmpkit.pipelines.identify_plan_files import write_identify_plan
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.batch_backend import BatchEvaluator
from zmpkit.simfit.cost import CostWeights
from zmpkit.simfit.design_experiments import DoubleSupportDesign, walk_designs
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.identifiability import identifiability
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc
from zmpkit.simfit.walk_plan import walk_trajectory

NAO = get_robot("nao")


def test_the_candidate_walks_vary_speed_and_step_time_within_the_step_length() -> None:
    designs = walk_designs(NAO, 6.0)
    walking = NAO.require_walking()
    assert len({(d.speed_mps, d.step_duration_s) for d in designs}) == len(designs) >= 4
    assert len({d.step_duration_s for d in designs}) >= 3
    assert all(d.speed_mps * d.step_duration_s <= walking.max_step_length_m for d in designs)
    assert all(d.duration_s == 6.0 for d in designs)


@pytest.mark.slow
def test_the_plan_judges_each_walk_as_the_fit_would_and_writes_its_protocols(
    tmp_path: Path,
) -> None:
    config = IdentifyPlanConfig(NAO, "M,G", quick=True, duration_s=3.0, workers=2)
    result = run_identify_plan(config, tmp_path)
    names = [p.name for p in result.parameters]
    assert names == ["pid_gain_scale", "gear_stiffness"]
    # The fit's own identifiability on the first recorded experiment alone, at the nominal values,
    # from its own batch: the plan's marginal resolutions are the same numbers.
    first = result.alone[0].experiments[0]
    folder = tmp_path / "recorded" / first
    experiments = tuple(read_experiments([folder], NAO))
    base = load_truth_doc(base_truth_path(NAO, None))
    problem = FitProblem(
        NAO, "M,G,S", result.parameters, base, experiments, CostWeights(), "expected"
    )
    nominal = np.array([p.nominal for p in result.parameters])
    evaluator = BatchEvaluator(problem, threads=2)
    centre = float(np.mean([t.total(problem.weights) for t in evaluator.costs([nominal])[0]]))
    judged = identifiability(problem, evaluator, nominal, centre, np.zeros(2))
    np.testing.assert_allclose(
        result.alone[0].marginal, [r.marginal_resolution for r in judged.parameters], rtol=1e-9
    )
    # The recommended set pins at least what its best experiment pins alone.
    assert sum(result.chosen[-1].pinned) >= max(sum(j.pinned) for j in result.alone)
    files = write_identify_plan(result, tmp_path)
    with files["plan"].open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2 * len(result.alone)
    assert set(rows[0]) == {"experiment", "parameter", "conditional_pct", "marginal_pct", "pins"}
    chosen = result.chosen[-1].experiments[0]
    protocol = tmp_path / "protocols" / chosen
    design = result.designs[chosen]
    table = np.loadtxt(protocol / "targets.csv", delimiter=",", skiprows=1)
    if isinstance(design, DoubleSupportDesign):
        np.testing.assert_allclose(
            table[:, 1:], double_support_targets(NAO, design.design).q_rad, atol=1e-6
        )
    else:
        height = NAO.require_walking().com_height_m
        plan = walk_trajectory(
            NAO, design.speed_mps, design.step_duration_s, design.duration_s, height
        )
        np.testing.assert_allclose(table[:, 1:], plan.q_rad, atol=1e-6)
    manifest = yaml.safe_load((protocol / "manifest.yaml").read_text(encoding="utf-8"))
    assert manifest["targets"]["file"] == "targets.csv"
    assert len(manifest["record"]["signals"]) == 4
