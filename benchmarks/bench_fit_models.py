"""Benchmark of building a generation's candidate simulations on the host: shared or not.

Usage::

    python benchmarks/bench_fit_models.py [--candidates N] [--experiments E] [--repeats R]
                                          [--threads N] [--json PATH]

Before any batch runs (on CPU threads or on a GPU), every candidate of a generation gets a
posed :class:`~zmpkit.sim.world.Simulation` per experiment: its truth, its description
(MJCF), the compiled model, the pose. On a GPU this host work is what no device removes.
Measured in the same run, best of ``--repeats``, for ``--candidates`` candidates of the
virtual NAO (every effect on; PID gain scale and gear stiffness near the fit tests' hidden
truth) and ``--experiments`` copies of the fit tests' recorded walk:

1. the truths (once per candidate);
2. :func:`~zmpkit.simfit.open_loop.posed_simulation` per experiment and candidate (each
   compiles the candidate's MJCF again: the baseline);
3. :func:`~zmpkit.simfit.open_loop.posed_simulations`: a candidate's description built
   and its MJCF compiled once, its other experiments starting from copies of that model.

Printed per candidate and experiment [ms] with the ratio to the baseline. Reported, never
asserted.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from harness import base_parser, print_table, write_run

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

__all__ = ["main", "measure"]

EFFECTS = "M,I,G,F,S"


def measure(ncandidates: int, nexperiments: int, repeats: int) -> dict[str, Any]:
    """Best wall time of each way [s] and the counts."""
    from helpers.simfit_data import record_walk, small_case
    from zmpkit.robots.registry import get_robot
    from zmpkit.simfit.experiments import read_experiments
    from zmpkit.simfit.open_loop import posed_simulation, posed_simulations
    from zmpkit.simfit.problem import FitProblem

    params, doc, truth = small_case()
    with tempfile.TemporaryDirectory() as tmp:
        experiments = (
            tuple(read_experiments([record_walk(Path(tmp))], get_robot("nao"))) * nexperiments
        )
    problem = FitProblem(get_robot("nao"), EFFECTS, params, doc, experiments)
    rng = np.random.default_rng(0)
    values = [
        np.asarray(truth) * np.exp(rng.normal(0.0, 0.05, len(truth))) for _ in range(ncandidates)
    ]

    def best(run: Any) -> float:
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            run()
            times.append(time.perf_counter() - start)
        return min(times)

    truths = [problem.truth(list(v)) for v in values]
    return {
        "candidates": ncandidates,
        "experiments": nexperiments,
        "truths_s": best(lambda: [problem.truth(list(v)) for v in values]),
        "per_experiment_s": best(
            lambda: [[posed_simulation(e, t, EFFECTS) for t in truths] for e in experiments]
        ),
        "shared_s": best(lambda: posed_simulations(experiments, truths, EFFECTS)),
    }


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--candidates", type=int, default=64)
    parser.add_argument("--experiments", type=int, default=3)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    if min(args.candidates, args.experiments, args.repeats) < 1:
        parser.error("--candidates, --experiments and --repeats must be >= 1")
    result = measure(args.candidates, args.experiments, args.repeats)
    n = args.candidates * args.experiments
    base = result["per_experiment_s"]
    cells = [
        ("truths (per candidate)", f"{1e3 * result['truths_s'] / args.candidates:.2f}", ""),
        ("posed_simulation per experiment", f"{1e3 * base / n:.2f}", "1.00"),
        (
            "posed_simulations (shared model)",
            f"{1e3 * result['shared_s'] / n:.2f}",
            f"{result['shared_s'] / base:.2f}",
        ),
    ]
    print_table(
        f"host work of a generation: {args.candidates} candidates x {args.experiments} experiments",
        ("what", "ms per candidate-experiment", "ratio"),
        cells,
        justify=("left", "right", "right"),
    )
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
