"""Recorded experiments for the simulator-fit tests: short NAO walks from a hidden truth."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit.simfit.parameters import FitParameter, default_parameters
from zmpkit.simfit.self_test import SelfTestPlan, perturbed_values, record_experiments
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

SEED = 5
WALK = (0.2, 1.5)
"""A 1.5 s walk at 0.2 m/s: about 4 s simulated, the smallest with a steady step."""


def small_case() -> tuple[tuple[FitParameter, ...], dict, np.ndarray]:
    """(the 2 quick NAO parameters, the shipped truth document, the hidden truth values)."""
    params = default_parameters("nao", "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path("nao", None))
    return params, doc, perturbed_values(params, SEED)


def record_walk(out: Path) -> Path:
    """Record one short walk of the virtual NAO (M, G, S) with the hidden truth."""
    params, doc, truth = small_case()
    plan = SelfTestPlan((WALK,), ())
    fit, _ = record_experiments("nao", plan, doc, params, truth, "M,G", SEED, out)
    return fit[0]
