"""Benchmark of a fit generation on MuJoCo Warp: the ``warp`` backend's costs, call by call.

Usage::

    python benchmarks/bench_warp_fit.py [--device cpu|cuda:0] [--candidates N] [--calls C]
                                        [--json PATH]

One recorded NAO walk (1.5 s at 0.2 m/s, M, G and S on; about 4 s simulated with the
pattern's standing) is the experiment, as in the fit's tests; a generation is
``--candidates`` candidates (PID gain scale, gear stiffness spread over their bounds)
evaluated by :class:`~zmpkit.simfit.batch_backend.BatchEvaluator` on MuJoCo Warp. Each of
``--calls`` generations is timed: the first builds the Warp model and data (and loads the
kernels from the persistent cache, or compiles them: run ``zmpkit warp warm-up`` first);
the later ones reuse them. Reported, never asserted. Without ``mujoco_warp`` it says so
and exits 0.
"""

from __future__ import annotations

import importlib.util
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from harness import base_parser, print_table, write_run

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

__all__ = ["main"]


def measure(device: str | None, ncandidates: int, calls: int) -> dict[str, Any]:
    """Wall time of each generation [s] and its cost totals."""
    from helpers.simfit_data import record_walk, small_case
    from zmpkit.simfit.batch_backend import BatchEvaluator
    from zmpkit.simfit.experiments import read_experiments
    from zmpkit.simfit.problem import FitProblem

    params, doc, _ = small_case()
    with tempfile.TemporaryDirectory() as tmp:
        experiments = tuple(read_experiments([record_walk(Path(tmp))], "nao"))
    problem = FitProblem("nao", "M,G,S", params, doc, experiments)
    units = [0.1 + 0.8 * i / max(1, ncandidates - 1) for i in range(ncandidates)]
    candidates = [[p.from_unit(u) for p in params] for u in units]
    evaluator = BatchEvaluator(problem, warp_device=device or "")
    rows = []
    for call in range(calls):
        start = time.perf_counter()
        costs = evaluator.costs(candidates)
        wall = time.perf_counter() - start
        totals = [c[0].total(problem.weights) for c in costs]
        rows.append({"call": call + 1, "wall_s": wall, "cost_totals": totals})
    return {"rows": rows, "candidates": ncandidates}


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--device", default=None, help="Warp device; default: Warp's default")
    parser.add_argument("--candidates", type=int, default=4)
    parser.add_argument("--calls", type=int, default=2)
    args = parser.parse_args(argv)
    if importlib.util.find_spec("mujoco_warp") is None:
        print("mujoco_warp is not installed: nothing to measure (pip install 'zmpkit[gpu]')")
        return 0
    result = measure(args.device, args.candidates, args.calls)
    cells = [(str(r["call"]), f"{r['wall_s']:.2f}") for r in result["rows"]]
    print_table(
        f"fit generations on MuJoCo Warp: {args.candidates} candidates x 1 walk",
        ("generation", "wall (s)"),
        cells,
        justify=("right", "right"),
    )
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
