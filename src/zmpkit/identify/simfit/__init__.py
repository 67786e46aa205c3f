"""zmpkit.identify.simfit: fit a simulator's effect parameters to recorded experiments.

Paper B §II (MoToFlex): "The simulation is optimized by Evolutionary Algorithms to fit a
physical robot." One concept per module:

- :mod:`~zmpkit.identify.simfit.parameters`: :class:`FitParameter` and the catalogue per
  robot and effect letter;
- :mod:`~zmpkit.identify.simfit.truth_doc`: the truth YAML edited by path, written back;
- :mod:`~zmpkit.identify.simfit.experiments`: recorded experiments and their folders;
- :mod:`~zmpkit.identify.simfit.walk_plan`: a walk's commanded trajectory, re-planned;
- :mod:`~zmpkit.identify.simfit.rollout`: replay an experiment on the simulator;
- :mod:`~zmpkit.identify.simfit.cost`: the normalised cost terms;
- :mod:`~zmpkit.identify.simfit.problem`: the problem as data, one evaluation;
- :mod:`~zmpkit.identify.simfit.backends`: serial, local process pool, Ray;
- :mod:`~zmpkit.identify.simfit.checkpoint`: CMA-ES state and history on disk;
- :mod:`~zmpkit.identify.simfit.optimizer`: the CMA-ES loop with resume;
- :mod:`~zmpkit.identify.simfit.identifiability`: profile and CMA-ES spread;
- :mod:`~zmpkit.identify.simfit.validation`: trunk oscillation and joint error checks;
- :mod:`~zmpkit.identify.simfit.self_test`: hidden perturbed truth, recording, recovery;
- :mod:`~zmpkit.identify.simfit.outputs`: the files of a fit.

The pipeline is :func:`zmpkit.pipelines.identify_sim.run_identify_sim`.
"""

from __future__ import annotations

from zmpkit.identify.simfit.backends import BACKENDS, DEFAULT_WORKERS, make_evaluator
from zmpkit.identify.simfit.cost import CostTerms, CostWeights, experiment_cost
from zmpkit.identify.simfit.experiments import (
    RecordedSignals,
    StepExperiment,
    WalkExperiment,
    read_experiments,
)
from zmpkit.identify.simfit.identifiability import ParameterIdentifiability, identifiability
from zmpkit.identify.simfit.optimizer import (
    CmaOptions,
    CmaResult,
    FitInterruptedError,
    FitProgress,
    run_cma,
)
from zmpkit.identify.simfit.parameters import FIT_LETTERS, FitParameter, default_parameters
from zmpkit.identify.simfit.problem import FitProblem, evaluate, simulate
from zmpkit.identify.simfit.self_test import RECOVERY_COLUMNS, RecoveryRow
from zmpkit.identify.simfit.validation import ReproductionCheck, reproduction_check

__all__ = [
    "BACKENDS",
    "DEFAULT_WORKERS",
    "FIT_LETTERS",
    "RECOVERY_COLUMNS",
    "CmaOptions",
    "CmaResult",
    "CostTerms",
    "CostWeights",
    "FitInterruptedError",
    "FitParameter",
    "FitProblem",
    "FitProgress",
    "ParameterIdentifiability",
    "RecordedSignals",
    "RecoveryRow",
    "ReproductionCheck",
    "StepExperiment",
    "WalkExperiment",
    "default_parameters",
    "evaluate",
    "experiment_cost",
    "identifiability",
    "make_evaluator",
    "read_experiments",
    "reproduction_check",
    "run_cma",
    "simulate",
]
