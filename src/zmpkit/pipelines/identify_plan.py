"""``zmpkit identify plan``: which experiments to record, before any is recorded.

Records every candidate experiment of the robot once from its nominal model
(:mod:`zmpkit.simfit.design_experiments`: designed double-support experiments, open-loop
walks, balance steps), evaluates the fit's cost of each on one shared
batch of candidates around the nominal values, and judges every experiment alone and the
set the greedy choice builds (:mod:`zmpkit.simfit.experiment_design`): which parameters
each pins, how finely, and which experiments to record.
:func:`run_identify_plan` writes only the recordings it makes under ``out/recorded``;
:func:`~zmpkit.pipelines.identify_plan_files.write_identify_plan` writes the tables and
the chosen experiments' protocols.
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.experiments.double_support import DESIGNS
from zmpkit.pipelines.identify_sim_config import IdentifySimConfig
from zmpkit.robots.robot import Robot
from zmpkit.simfit.batch_backend import BatchEvaluator
from zmpkit.simfit.cost import CostWeights
from zmpkit.simfit.design_experiments import (
    Design,
    double_support_designs,
    record_design,
    record_step_designs,
    scratch_folder,
    step_designs,
    walk_designs,
    write_nominal_truth,
)
from zmpkit.simfit.experiment_design import (
    ExperimentCosts,
    SetJudgement,
    design_candidates,
    greedy_design,
    judge_set,
)
from zmpkit.simfit.experiments import Experiment, StepExperiment, read_experiments
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

__all__ = ["IdentifyPlanConfig", "IdentifyPlanResult", "run_identify_plan"]

PlanProgress = Callable[[str, int, int], None]
"""``progress(stage, done, total)``."""


@dataclass(frozen=True)
class IdentifyPlanConfig:
    """What to plan for.

    Attributes:
        robot: the robot (one with a fit catalogue).
        effects: effect letters whose parameters the fit would fit (as ``identify sim``).
        quick: plan for the quick fit's parameters.
        duration_s: each candidate walk's length [s].
        workers: threads of the batches.
        seed: seed of the recordings' sensor noise.
    """

    robot: Robot
    effects: str = "M,G"
    quick: bool = False
    duration_s: float = 6.0
    workers: int = 2
    seed: int = 1

    def __post_init__(self) -> None:
        if not 1.0 <= self.duration_s <= 60.0:
            raise ParameterError(
                f"duration must lie in [1, 60] s for a candidate walk; got {self.duration_s}"
            )
        self.fit_config()  # the effects and the robot's catalogue, checked as identify sim does

    def fit_config(self) -> IdentifySimConfig:
        """The ``identify sim`` configuration the plan is for."""
        return IdentifySimConfig(
            robot=self.robot, effects=self.effects, quick=self.quick, self_test=True,
            workers=self.workers, seed=self.seed,
        )  # fmt: skip


@dataclass(frozen=True, eq=False)
class IdentifyPlanResult:
    """A plan.

    Attributes:
        config: what was planned for.
        parameters: the fitted parameters, in the judgements' order.
        candidates: the parameter values every experiment was evaluated at [units], in
            :func:`~zmpkit.simfit.experiment_design.design_candidates`' order.
        costs: each experiment's cost on every candidate [-].
        alone: each candidate experiment judged alone.
        chosen: the greedy choice's sets, one per experiment added (the last recommended).
        designs: the recorded candidates with a protocol, by experiment name.
        dropped: candidate experiments the nominal robot could not complete, with why.
        seconds: the plan's wall time [s].
    """

    config: IdentifyPlanConfig
    parameters: tuple[FitParameter, ...]
    candidates: tuple[NDArray[np.float64], ...]
    costs: tuple[ExperimentCosts, ...]
    alone: tuple[SetJudgement, ...]
    chosen: tuple[SetJudgement, ...]
    designs: dict[str, Design]
    dropped: tuple[str, ...]
    seconds: float


def run_identify_plan(
    config: IdentifyPlanConfig, out_dir: str | Path, progress: PlanProgress | None = None
) -> IdentifyPlanResult:
    """Record the candidates, evaluate them on one batch, judge them (module docstring)."""
    start = time.perf_counter()
    fit = config.fit_config()
    robot, params = config.robot, fit.fit_parameters()
    base_doc = load_truth_doc(base_truth_path(robot, None))
    out = Path(out_dir)
    experiments, designs, dropped = _record(
        config, fit, base_doc, params, out / "recorded", progress
    )
    if not experiments:
        raise ParameterError(
            "the nominal robot completed none of the candidate experiments: " + "; ".join(dropped)
        )
    problem = FitProblem(
        robot, fit.sim_effects, params, base_doc, tuple(experiments), CostWeights(), "expected"
    )
    candidates = design_candidates([p.nominal for p in params])
    if progress is not None:
        progress("evaluating", 0, len(candidates))
    rows = BatchEvaluator(problem, threads=config.workers).costs(candidates)
    if progress is not None:
        progress("evaluating", len(candidates), len(candidates))
    per_experiment = [
        ExperimentCosts(x.name, np.array([row[e].total(problem.weights) for row in rows]))
        for e, x in enumerate(experiments)
    ]
    alone = tuple(judge_set([e], len(params)) for e in per_experiment)
    chosen = tuple(greedy_design(per_experiment, len(params)))
    seconds = time.perf_counter() - start
    return IdentifyPlanResult(
        config, params, tuple(candidates), tuple(per_experiment), alone, chosen, designs,
        tuple(dropped), seconds,
    )  # fmt: skip


def _record(
    config: IdentifyPlanConfig,
    fit: IdentifySimConfig,
    base_doc: dict,
    params: tuple[FitParameter, ...],
    out: Path,
    progress: PlanProgress | None,
) -> tuple[list[Experiment], dict[str, Design], list[str]]:
    """Record every candidate from the nominal robot; the experiments, designs and drops."""
    robot = config.robot
    recorded_effects = "S" if fit.physics_effects == "none" else f"{fit.physics_effects},S"
    designs: list[Design] = list(double_support_designs())
    if robot.require_fit().experiment == "walk":
        designs += walk_designs(robot, config.duration_s)
    scratch = scratch_folder()
    folders: list[Path] = []
    recorded: dict[str, Design] = {}
    dropped: list[str] = []
    try:
        truth = write_nominal_truth(base_doc, params, scratch)
        if robot.require_fit().experiment != "walk":
            targets = step_designs(robot)
            folders.append(record_step_designs(robot, targets, truth, recorded_effects,
                                               config.seed, out))  # fmt: skip
        for k, design in enumerate(designs):
            if progress is not None:
                progress("recording", k, len(designs))
            folder = record_design(robot, design, truth, recorded_effects, config.seed + k, out)
            if folder is None:
                dropped.append(f"{design.name}: the nominal robot fell")
                continue
            folders.append(folder)
            recorded[folder.name] = design
        if progress is not None:
            progress("recording", len(designs), len(designs))
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    experiments = list(read_experiments(folders, robot)) if folders else []
    return [_named(x) for x in experiments], recorded, dropped


def _named(experiment: Experiment) -> Experiment:
    """A designed double-support trial named by its folder (its design), not its trial file."""
    if isinstance(experiment, StepExperiment) and "/" in experiment.name:
        folder, _ = experiment.name.split("/", 1)
        if folder in DESIGNS:
            return replace(experiment, name=folder)
    return experiment
