"""A full-length recorded walk and candidates around its hidden truth, for the Warp benchmarks.

One 10 s walk at 0.2 m/s of the virtual NAO (the fit's tests' robot), recorded with every
effect (M, I, G, F and S) from the hidden truth of the fit's tests (PID gain scale, gear
stiffness, moved by ``SEED``); the candidates are that truth scaled by a few factors
(near-optimal: within 3 %; farther: 10 %, 20 %) and the nominal values.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

__all__ = ["EFFECTS", "FACTORS", "ROBOT", "LongWalk", "long_walk"]

ROBOT = "nao"
"""The walking robot of the fit's tests."""
EFFECTS = "M,I,G,F,S"
"""Every effect, as the fit simulates them."""
FACTORS = (1.0, 1.01, 0.99, 1.03, 0.97, 1.1, 0.8)
"""Candidates: the hidden truth times these factors [-] (and then the nominal values)."""


@dataclass(frozen=True)
class LongWalk:
    """The fit problem of one long walk and its candidates.

    Attributes:
        problem: the fit problem (one walk experiment).
        labels: a name per candidate.
        candidates: parameter values per candidate [units of each parameter].
    """

    problem: object
    labels: tuple[str, ...]
    candidates: tuple[tuple[float, ...], ...]


def long_walk(out: Path, duration_s: float = 10.0, speed_mps: float = 0.2) -> LongWalk:
    """Record the walk into ``out`` and build the problem and candidates."""
    from helpers.simfit_data import SEED, small_case
    from zmpkit.robots.registry import get_robot
    from zmpkit.simfit.experiments import read_experiments
    from zmpkit.simfit.problem import FitProblem
    from zmpkit.simfit.self_test import SelfTestPlan, record_experiments

    robot = get_robot(ROBOT)
    params, doc, truth = small_case()
    plan = SelfTestPlan(((speed_mps, duration_s),), ())
    recorded = EFFECTS.replace(",S", "")
    paths, _ = record_experiments(robot, plan, doc, params, truth, recorded, SEED, out)
    experiments = tuple(read_experiments(paths, robot))
    problem = FitProblem(robot, EFFECTS, params, doc, experiments)
    labels = [f"truth x {f:g}" for f in FACTORS] + ["nominal"]
    values = [tuple(float(v) for v in np.asarray(truth) * f) for f in FACTORS]
    values.append(tuple(float(p.nominal) for p in params))
    return LongWalk(problem, tuple(labels), tuple(values))


def long_walk_arguments(
    parser: argparse.ArgumentParser, argv: list[str] | None
) -> argparse.Namespace | None:
    """Add ``--device`` and ``--duration`` and parse; None (said why) without MuJoCo Warp."""
    parser.add_argument("--device", default="cpu", help="Warp device (default: cpu)")
    parser.add_argument("--duration", type=float, default=10.0, help="walk duration [s]")
    args = parser.parse_args(argv)
    if importlib.util.find_spec("mujoco_warp") is None:
        print("mujoco_warp is not installed: nothing to measure (pip install 'zmpkit[gpu]')")
        return None
    return args
