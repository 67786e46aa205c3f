"""How rough is the fit's cost near the truth, term by term?

Usage::

    python examples/cost_roughness.py OUT [--robot nao] [--effects M,G] [--quick]
                                      [--span 0.01] [--points 21] [--workers N]
                                      [--expected-readings]

Records the self-test's experiments from a robot whose hidden truth is the self-test's
(:func:`~zmpkit.simfit.self_test.perturbed_values`), then evaluates the fit's cost along a
line through the truth in each parameter (``points`` values over ± ``span``, relative) and
splits it into its terms (joint, ZMP, trunk spectrum: :mod:`zmpkit.simfit.cost`). Per term
and parameter a quadratic is fitted to the line; the *roughness* is the RMS of what the
quadratic leaves [-], the *rise* the quadratic's mean rise at ± ``span`` [-], and the *jump*
the largest second difference between neighbouring points [-]. A smooth cost has roughness
well below its rise; a cost whose term jumps (contact timing moving by a physics step)
misleads the curvature, the Hessian and the profiles built on it.

Writes ``OUT/roughness.csv`` (parameter, term, rise, roughness, jump, roughness/rise) and
``OUT/lines.csv`` (every point's terms) and prints the table. The truth is read only to place
the lines (this example's question, not a fit).
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

import numpy as np

from zmpkit.pipelines.identify_sim import IdentifySimConfig
from zmpkit.simfit.batch_backend import BatchEvaluator
from zmpkit.simfit.cost import CostWeights
from zmpkit.simfit.experiments import read_experiments
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.self_test import (
    SelfTestPlan,
    perturbed_values,
    record_experiments,
    self_test_plan,
)
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

TERMS = ("joint", "zmp", "spectrum")


def main() -> None:
    """Record, walk the lines, write the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--robot", default="nao")
    parser.add_argument("--effects", default="M,G")
    parser.add_argument("--quick", action="store_true", help="the quick self-test's walks")
    parser.add_argument("--span", type=float, default=0.01, help="relative half-width [-]")
    parser.add_argument("--points", type=int, default=21)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--expected-readings", action="store_true")
    args = parser.parse_args()
    config = IdentifySimConfig(
        robot=args.robot, effects=args.effects, self_test=True, seed=args.seed, quick=args.quick
    )
    robot = config.robot
    params = config.fit_parameters()
    doc = load_truth_doc(base_truth_path(robot, None))
    truth = perturbed_values(params, args.seed)
    plan = SelfTestPlan(self_test_plan(robot, args.quick).fit, ())
    start = time.perf_counter()
    fit_dirs, _ = record_experiments(
        robot, plan, doc, params, truth, config.physics_effects, args.seed, args.out
    )
    experiments = tuple(read_experiments(fit_dirs, robot))
    readings = "expected" if args.expected_readings else "sampled"
    weights = CostWeights()
    problem = FitProblem(robot, config.sim_effects, params, doc, experiments, weights, readings)
    evaluator = BatchEvaluator(problem, threads=args.workers)
    steps = np.linspace(-args.span, args.span, args.points)
    rows, lines = [], []
    for i, p in enumerate(params):
        candidates = []
        for s in steps:
            v = truth.copy()
            v[i] = truth[i] * (1.0 + s)
            candidates.append(v)
        terms = evaluator.costs(candidates)
        values = {t: np.array([_term(c, t, problem) for c in terms]) for t in TERMS}
        for k, s in enumerate(steps):
            lines.append((p.name, f"{s:.6g}", *(f"{values[t][k]:.9g}" for t in TERMS)))
        for t in TERMS:
            rows.append((p.name, t, *_roughness(steps, values[t])))
    with (args.out / "lines.csv").open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(("parameter", "relative_step", *TERMS))
        w.writerows(lines)
    with (args.out / "roughness.csv").open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(("parameter", "term", "rise", "roughness", "jump", "roughness_over_rise"))
        for name, term, rise, rough, jump in rows:
            ratio = rough / rise if rise > 0 else float("inf")
            w.writerow((name, term, f"{rise:.4g}", f"{rough:.4g}", f"{jump:.4g}", f"{ratio:.4g}"))
            print(
                f"{name:22s} {term:9s} rise {rise:10.3g} roughness {rough:10.3g} "
                f"jump {jump:10.3g}  ratio {ratio:.3g}"
            )
    seconds = time.perf_counter() - start
    print(f"{readings} readings, {len(experiments)} experiments, {seconds:.0f} s")


def _term(per_experiment: list, term: str, problem: FitProblem) -> float:
    """The mean over experiments of one weighted squared term [-]."""
    w = getattr(problem.weights, term)
    return float(np.mean([w * getattr(c, term) ** 2 for c in per_experiment]))


def _roughness(steps: np.ndarray, values: np.ndarray) -> tuple[float, float, float]:
    """(rise, roughness, jump) of one term along one line (module docstring) [-]."""
    coef = np.polyfit(steps, values, 2)
    fitted = np.polyval(coef, steps)
    rough = float(np.sqrt(np.mean((values - fitted) ** 2)))
    rise = float(0.5 * (np.polyval(coef, steps[0]) + np.polyval(coef, steps[-1]))
                 - np.polyval(coef, 0.0))  # fmt: skip
    jump = float(np.max(np.abs(np.diff(values, 2)))) if values.size > 2 else 0.0
    return rise, rough, jump


if __name__ == "__main__":
    main()
