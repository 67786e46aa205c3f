"""zmpkit.simfit: fit a simulator's effect parameters to recorded experiments.

Paper B §II (MoToFlex): "The simulation is optimized by Evolutionary Algorithms to fit a
physical robot." One concept per module:

- :mod:`~zmpkit.simfit.parameters`: :class:`FitParameter` and the catalogue per
  robot and effect letter;
- :mod:`~zmpkit.simfit.truth_doc`: the truth YAML edited by path, written back;
- :mod:`~zmpkit.simfit.experiments`: recorded experiments and their folders;
- :mod:`~zmpkit.simfit.walk_plan`: a walk's commanded trajectory, re-planned (a fallen
  walk's up to its fall);
- :mod:`~zmpkit.simfit.closed_loop`: a walk of a feedback controller, re-simulated with it;
- :mod:`~zmpkit.simfit.shooting_window`: a walk log of any controller cut into windows,
  each started from its measured state (multiple shooting); the log's paths
  (:mod:`~zmpkit.simfit.log_experiment`), the pose from the sensors alone
  (:mod:`~zmpkit.simfit.log_kinematics`) and a window's replay
  (:mod:`~zmpkit.simfit.shooting`);
- :mod:`~zmpkit.simfit.rollout`: replay an experiment on the simulator;
- :mod:`~zmpkit.simfit.cost`: the normalised cost terms;
- :mod:`~zmpkit.simfit.problem`: the problem as data, one evaluation;
- :mod:`~zmpkit.simfit.backends`: serial, local batches, process pool
  (:mod:`~zmpkit.simfit.pool_backend`), Ray, Warp;
- :mod:`~zmpkit.simfit.checkpoint`: CMA-ES state and history on disk, as data (JSON and
  ``.npz``, no pickle): :mod:`~zmpkit.simfit.checkpoint_data` (arrays, random generators),
  :mod:`~zmpkit.simfit.checkpoint_history` (the generations),
  :mod:`~zmpkit.simfit.cma_state` and :mod:`~zmpkit.simfit.cma_entries` (the ``cma``
  strategy written and rebuilt);
- :mod:`~zmpkit.simfit.optimizer`: the CMA-ES loop with resume;
- :mod:`~zmpkit.simfit.cost_hessian`: the cost's Hessian, marginal resolutions, loose directions;
- :mod:`~zmpkit.simfit.identifiability`: profile, marginal resolution and CMA-ES spread;
- :mod:`~zmpkit.simfit.adequacy`: does the model explain the data (best cost against the
  noise floor, residual structure);
- :mod:`~zmpkit.simfit.noise_intervals`: 95 % intervals the data's noise leaves;
- :mod:`~zmpkit.simfit.refit_intervals`: 95 % intervals that hold the estimator's bias, from
  replicas recorded again through the data's pipeline (a ``zmpkit walk`` log walked again:
  :mod:`~zmpkit.simfit.pipeline_replicas`; any log's windows replayed again:
  :mod:`~zmpkit.simfit.window_replicas`) and re-fitted (:mod:`~zmpkit.simfit.local_refit`);
- :mod:`~zmpkit.simfit.validation`: trunk oscillation and joint error checks;
- :mod:`~zmpkit.simfit.self_test`: hidden perturbed truth, recording, recovery;
- :mod:`~zmpkit.simfit.outputs`: the files of a fit.

The pipeline is :func:`zmpkit.pipelines.identify_sim.run_identify_sim`.
"""

from __future__ import annotations

from zmpkit.simfit.backends import BACKENDS, DEFAULT_WORKERS, make_evaluator
from zmpkit.simfit.cost import CostTerms, CostWeights, experiment_cost
from zmpkit.simfit.experiments import (
    ShootingWindow,
    StepExperiment,
    WalkExperiment,
    read_experiments,
)
from zmpkit.simfit.identifiability import (
    Identifiability,
    ParameterIdentifiability,
    identifiability,
)
from zmpkit.simfit.optimizer import (
    CmaOptions,
    CmaResult,
    FitInterruptedError,
    FitProgress,
    run_cma,
)
from zmpkit.simfit.parameters import FIT_LETTERS, FitParameter, default_parameters
from zmpkit.simfit.problem import FitProblem, evaluate, simulate
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.self_test import RECOVERY_COLUMNS, RecoveryRow
from zmpkit.simfit.validation import ReproductionCheck, reproduction_check

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
    "Identifiability",
    "ParameterIdentifiability",
    "RecordedSignals",
    "RecoveryRow",
    "ReproductionCheck",
    "ShootingWindow",
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
