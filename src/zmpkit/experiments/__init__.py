"""Experiments on virtual (or real) robots: configuration in, a dataset folder out.

- :mod:`~zmpkit.experiments.config`: :class:`StepExperimentConfig`, :class:`PushConfig`.
- :mod:`~zmpkit.experiments.lean`: the ankle-strategy lean and its design lean length.
- :mod:`~zmpkit.experiments.trial`: :func:`run_step_trial`, one recorded trial.
- :mod:`~zmpkit.experiments.dataset`: the dataset folder and :func:`read_step_dataset`.
- :mod:`~zmpkit.experiments.sweep`: :func:`run_step_sweep`, resumable, on a process pool.
- :mod:`~zmpkit.experiments.response`: measured vs expected ZMP, the steady-state table.
"""

from zmpkit.experiments.config import (
    DEFAULT_TARGETS_M,
    MAX_HOLD_S,
    MAX_PUSH_DURATION_S,
    MAX_PUSH_FORCE_N,
    PUSH_POINTS,
    PushConfig,
    StepExperimentConfig,
    parse_targets,
    trial_file_name,
)
from zmpkit.experiments.dataset import (
    DATASET_FORMAT,
    META_FILE,
    StepDataset,
    read_step_dataset,
)
from zmpkit.experiments.lean import LeanModel, design_lean_model, lean_angle
from zmpkit.experiments.response import (
    STEADY_STATE_COLUMNS,
    STEADY_WINDOW_S,
    TrialResponse,
    dataset_trials,
    measured_zmp,
    step_responses,
    trial_response,
    write_steady_state_csv,
)
from zmpkit.experiments.sweep import DEFAULT_WORKERS, MAX_WORKERS, run_step_sweep
from zmpkit.experiments.trial import CONTROL_PERIOD_S, LeanController, run_step_trial
from zmpkit.experiments.trial_record import StepTrialRecord

__all__ = [
    "CONTROL_PERIOD_S",
    "DATASET_FORMAT",
    "DEFAULT_TARGETS_M",
    "DEFAULT_WORKERS",
    "MAX_HOLD_S",
    "MAX_PUSH_DURATION_S",
    "MAX_PUSH_FORCE_N",
    "MAX_WORKERS",
    "META_FILE",
    "PUSH_POINTS",
    "STEADY_STATE_COLUMNS",
    "STEADY_WINDOW_S",
    "LeanController",
    "LeanModel",
    "PushConfig",
    "StepDataset",
    "StepExperimentConfig",
    "StepTrialRecord",
    "TrialResponse",
    "dataset_trials",
    "design_lean_model",
    "lean_angle",
    "measured_zmp",
    "parse_targets",
    "read_step_dataset",
    "run_step_sweep",
    "run_step_trial",
    "step_responses",
    "trial_file_name",
    "trial_response",
    "write_steady_state_csv",
]
