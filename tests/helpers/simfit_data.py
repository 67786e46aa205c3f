"""Recorded experiments for the simulator-fit tests: short NAO walks from a hidden truth."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit.robots.registry import get_robot
from zmpkit.simfit.parameters import FitParameter, default_parameters
from zmpkit.simfit.self_test import SelfTestPlan, perturbed_values, record_experiments
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

NAO = get_robot("nao")
SEED = 5
WALK = (0.2, 1.5)
"""A 1.5 s walk at 0.2 m/s: about 4 s simulated, the smallest with a steady step."""


def small_case() -> tuple[tuple[FitParameter, ...], dict, np.ndarray]:
    """(the 2 quick NAO parameters, the shipped truth document, the hidden truth values)."""
    params = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(NAO, None))
    return params, doc, perturbed_values(params, SEED)


def record_walk(out: Path) -> Path:
    """Record one short walk of the virtual NAO (M, G, S) with the hidden truth."""
    params, doc, truth = small_case()
    plan = SelfTestPlan((WALK,), ())
    fit, _ = record_experiments(NAO, plan, doc, params, truth, "M,G", SEED, out)
    return fit[0]


def record_feedback_walk(
    out: Path, controller: str = "zmpip", speed_mps: float = 0.2, seed: int = 3
) -> Path:
    """Record one short walk of the shipped virtual NAO (M, G, S) with a feedback controller.

    Written as ``zmpkit walk`` writes it (``summary.json`` + ``timeseries.csv``).
    """
    from zmpkit.experiments.walk import run_walk_trial
    from zmpkit.experiments.walk_config import WalkConfig
    from zmpkit.experiments.walk_dataset import (
        SERIES_FILE,
        SUMMARY_FILE,
        write_series,
        write_summary,
    )

    config = WalkConfig(
        robot=NAO,
        speed_mps=speed_mps,
        duration_s=WALK[1],
        effects="M,G,S",
        seed=seed,
        figures=False,
        controller=controller,
    )
    trial = run_walk_trial(config)
    out.mkdir(parents=True, exist_ok=True)
    write_summary(out / SUMMARY_FILE, trial.summary)
    write_series(out / SERIES_FILE, trial.pattern, trial.record)
    return out
