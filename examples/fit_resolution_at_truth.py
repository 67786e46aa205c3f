"""How finely can a simulator fit pin each parameter down, before running it?

Usage::

    python examples/fit_resolution_at_truth.py OUT [--robot nao] [--effects M,G,F,S,C]
                                               [--quick] [--designed] [--workers N] [--seed S]
                                               [--weights JOINT,ZMP,SPECTRUM]

Records the self-test's experiments (:func:`~zmpkit.simfit.self_test.self_test_plan`) from
a robot whose hidden truth is the self-test's (every fitted parameter moved 8-25 % by the
seed), then measures the fit's cost at that truth — where a perfect fit ends — with each
parameter moved by ±10 % and each pair moved together (:mod:`zmpkit.simfit.identifiability`,
:mod:`zmpkit.simfit.cost_hessian`): 2n + n(n-1) + 1 candidates, one batch. Each parameter's
*resolution* is the relative change that raises the cost visibly: *conditional* with the
others held (the 1-D profile), *marginal* with the others free to compensate (from the
cost's Hessian). A parameter with a marginal resolution within 10 % is identifiable from
these experiments, and a fit that converges can be asked to recover it to about that; the
loose directions name the combinations the data cannot separate.
A full-effect fit (M, G, F, S and C: 12 parameters on the NAO) needs a population of
hundreds to converge, a GPU's job; this says beforehand which of its parameters the data
can pin down, and how finely, on a CPU in minutes.

``--designed`` adds the designed double-support experiments
(:mod:`zmpkit.experiments.double_support`) to the walks or steps. Before the profile it
prints each experiment's cost terms at the truth and their scatter under the roughness
probes (1.4826 × the median absolute deviation, the measure
:mod:`zmpkit.simfit.identifiability` takes of the whole cost), and writes them to
``OUT/terms_at_truth.csv``.

Writes ``OUT/resolution_at_truth.csv`` (parameter, truth, cost at -10 %, at the truth, at
+10 %, conditional and marginal resolution [%], identifiable from the marginal),
``OUT/sloppy_directions.csv`` and ``OUT/hessian.csv`` and prints them. The truth is read
only to place the profile (it is this example's question, not a fit).
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

from zmpkit.pipelines.identify_sim import IdentifySimConfig
from zmpkit.simfit.batch_backend import BatchEvaluator
from zmpkit.simfit.cost import CostTerms, CostWeights
from zmpkit.simfit.experiments import Experiment, read_experiments
from zmpkit.simfit.identifiability import (
    IDENTIFIABLE_WITHIN,
    identifiability,
    roughness_candidates,
)
from zmpkit.simfit.outputs import write_sloppy_directions_csv
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.self_test import (
    SelfTestPlan,
    perturbed_values,
    record_experiments,
    self_test_plan,
)
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc


def main() -> None:
    """Record, profile, write the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--robot", default="nao")
    parser.add_argument("--effects", default="M,G,F,S,C")
    parser.add_argument("--quick", action="store_true", help="the quick self-test's walks")
    parser.add_argument(
        "--designed", action="store_true", help="the designed double-support experiments too"
    )
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument(
        "--expected-readings",
        action="store_true",
        help="the fit's simulated sensors without noise and quantisation (offsets kept)",
    )
    parser.add_argument(
        "--weights", default="1,1,1", help="the cost terms' weights: joint,zmp,spectrum"
    )
    args = parser.parse_args()
    config = IdentifySimConfig(
        robot=args.robot, effects=args.effects, self_test=True, seed=args.seed
    )
    robot = config.robot  # resolved once, by the config
    params = config.fit_parameters()  # the whole catalogue of these effects (not --quick's)
    doc = load_truth_doc(base_truth_path(robot, None))
    truth = perturbed_values(params, args.seed)
    designs = self_test_plan(robot, args.quick, designed=args.designed).designs
    plan = SelfTestPlan(self_test_plan(robot, args.quick).fit, (), designs=designs)
    start = time.perf_counter()
    fit_dirs, _ = record_experiments(
        robot, plan, doc, params, truth, config.physics_effects, args.seed, args.out
    )
    experiments = tuple(read_experiments(fit_dirs, robot))
    weights = CostWeights(*(float(x) for x in args.weights.split(",")))
    readings = "expected" if args.expected_readings else "sampled"
    problem = FitProblem(robot, config.sim_effects, params, doc, experiments, weights, readings)
    evaluator = BatchEvaluator(problem, threads=args.workers)
    at_truth = evaluator.costs([truth])[0]
    cost0 = float(np.mean([t.total(problem.weights) for t in at_truth]))
    _write_terms(args.out, experiments, problem, at_truth, evaluator, truth)
    judged = identifiability(problem, evaluator, truth, cost0, np.zeros(len(params)))
    rows = judged.parameters
    seconds = time.perf_counter() - start
    path = args.out / "resolution_at_truth.csv"
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(
            ("parameter", "truth", "cost_minus", "cost_truth", "cost_plus", "resolution_pct",
             "marginal_resolution_pct", "identifiable")
        )  # fmt: skip
        for p, r, v in zip(params, rows, truth, strict=True):
            writer.writerow(
                (p.name, f"{v:.6g}", f"{r.cost_minus:.6g}", f"{r.cost_opt:.6g}",
                 f"{r.cost_plus:.6g}", _pct(r.resolution), _pct(r.marginal_resolution),
                 str(r.marginal_resolution <= IDENTIFIABLE_WITHIN).lower())
            )  # fmt: skip
            print(
                f"{p.name:22s} truth {v:<10.5g} resolution {_pct(r.resolution):>7s} %"
                f"  marginal {_pct(r.marginal_resolution):>7s} %"
            )
    names = [p.name for p in params]
    with (args.out / "hessian.csv").open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(("parameter", *names))
        for name, row in zip(names, judged.hessian, strict=True):
            writer.writerow((name, *(f"{x:.6g}" for x in row)))
    write_sloppy_directions_csv(args.out / "sloppy_directions.csv", judged.sloppy)
    for k, d in enumerate(judged.sloppy):
        parts = ", ".join(f"{name} {value:+.2f}" for name, value in d.components)
        print(f"loose direction {k + 1}: ±{_pct(d.resolution)} %: {parts}")
    held = sum(r.resolution <= IDENTIFIABLE_WITHIN for r in rows)
    free = sum(r.marginal_resolution <= IDENTIFIABLE_WITHIN for r in rows)
    print(
        f"within {100 * IDENTIFIABLE_WITHIN:g} %: {held} of {len(params)} parameters with the "
        f"others held, {free} with them free; cost at the truth {cost0:.3g}, level around it "
        f"{judged.level:.3g}, roughness {judged.roughness:.3g}, visible rise {judged.rise:.3g}; "
        f"{len(experiments)} experiments, {len(params) * (len(params) + 1) + 1} candidates, "
        f"{seconds:.0f} s; {path}"
    )


_TERMS = ("joint", "zmp", "force", "spectrum")


def _write_terms(
    out: Path,
    experiments: tuple[Experiment, ...],
    problem: FitProblem,
    at_truth: list[CostTerms],
    evaluator: BatchEvaluator,
    truth: np.ndarray,
) -> None:
    """Each experiment's weighted squared terms at the truth and their scatter nearby."""
    probes = evaluator.costs(roughness_candidates(np.asarray(truth, dtype=float)))
    weights = [getattr(problem.weights, name) for name in _TERMS]

    def squares(terms: CostTerms) -> list[float]:
        return [w * getattr(terms, name) ** 2 for w, name in zip(weights, _TERMS, strict=True)]

    rows = []
    for k, experiment in enumerate(experiments):
        near = np.array([squares(row[k]) for row in probes])
        median = np.median(near, axis=0)
        scatter = 1.4826 * np.median(np.abs(near - median), axis=0)
        rows.append((experiment.name, squares(at_truth[k]), scatter))
        print(
            f"{experiment.name:28s} at the truth "
            + " ".join(f"{n} {v:.2g}" for n, v in zip(_TERMS, rows[-1][1], strict=True))
            + " | scatter "
            + " ".join(f"{v:.2g}" for v in scatter)
        )
    with (out / "terms_at_truth.csv").open("w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(
            ("experiment", *(f"{n}_at_truth" for n in _TERMS), *(f"{n}_scatter" for n in _TERMS))
        )
        for name, at, spread in rows:
            writer.writerow((name, *(f"{v:.6g}" for v in at), *(f"{v:.6g}" for v in spread)))


def _pct(fraction: float) -> str:
    return f"{100 * fraction:.3g}" if math.isfinite(fraction) else "inf"


if __name__ == "__main__":
    main()
