"""Benchmark of the simulator fit: rollouts per second and wall time per CMA-ES generation.

Usage::

    python benchmarks/bench_simfit.py [--json PATH] [--candidates N] [--duration S]
                                      [--workers W] [--repeats R]

One recorded NAO walk (``--duration`` s of walking at 0.2 m/s, M, G and S on; the pattern
adds 2.6 s of standing) is the experiment; a generation is ``--candidates`` candidate
parameter vectors (PID gain scale, gear stiffness) evaluated on it, i.e. ``N`` walks of
``S`` s. Measured (best of ``--repeats``), every effect native MuJoCo (dcmotor actuators,
tendon gears):

1. ``serial``: every rollout in this process;
2. ``local pool``: :class:`~zmpkit.identify.simfit.backends.LocalPoolEvaluator` with
   ``--workers`` processes (started before timing; their start-up is reported apart).

Issue 7's target: a generation of 12 × 10 s walks in <= 1 s. Speed is reported, never
asserted. An MJX batched path (GPU) is not implemented (see the report of issue 7).
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from harness import base_parser, environment, print_table, write_json
from zmpkit.identify.simfit.backends import LocalPoolEvaluator, SerialEvaluator
from zmpkit.identify.simfit.experiments import read_experiments
from zmpkit.identify.simfit.parameters import default_parameters
from zmpkit.identify.simfit.problem import FitProblem
from zmpkit.identify.simfit.truth_doc import base_truth_path, load_truth_doc
from zmpkit.pipelines.walk import WalkConfig, run_walk

__all__ = ["main"]


def make_problem(folder: Path, duration_s: float) -> FitProblem:
    """Record one walk into ``folder`` and wrap it as a 2-parameter NAO fit problem."""
    run_walk(WalkConfig(duration_s=duration_s, effects="M,G,S", figures=False), folder)
    params = default_parameters("nao", "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path("nao", None))
    return FitProblem("nao", "M,G,S", params, doc, tuple(read_experiments([folder], "nao")))


def candidates(n: int) -> list[list[float]]:
    """``n`` parameter vectors spread over the bounds (a CMA-ES generation's worth)."""
    rng = np.random.default_rng(0)
    return [[float(rng.uniform(0.5, 0.9)), float(rng.uniform(800, 2000))] for _ in range(n)]


def best_generation(evaluator: Any, batch: list[list[float]], repeats: int) -> float:
    """Best wall time of one ``evaluator.costs(batch)`` [s]."""
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        evaluator.costs(batch)
        best = min(best, time.perf_counter() - start)
    return best


def measure(n: int, duration_s: float, workers: int, repeats: int) -> dict[str, Any]:
    """Walls of a generation, serial and on the pool, and the pool's start-up [s]."""
    with tempfile.TemporaryDirectory() as folder:
        problem = make_problem(Path(folder) / "walk", duration_s)
        batch = candidates(n)
        serial = SerialEvaluator(problem)
        serial.costs(batch[:1])  # plans the walk's trajectory once (cached), as a worker does
        serial_s = best_generation(serial, batch, repeats)
        start = time.perf_counter()
        pool = LocalPoolEvaluator(problem, workers)
        pool.costs(batch[:workers])  # start the workers, plan the walk in each
        startup_s = time.perf_counter() - start
        try:
            pool_s = best_generation(pool, batch, repeats)
        finally:
            pool.close()
    simulated = problem.experiments[0].signals.time_s[-1]
    rows = [
        {"backend": "serial", "generation_s": serial_s, "rollouts_per_s": n / serial_s},
        {
            "backend": f"local pool ({workers})",
            "generation_s": pool_s,
            "rollouts_per_s": n / pool_s,
        },
    ]
    return {"rows": rows, "pool_startup_s": startup_s, "simulated_s_per_rollout": simulated}


def show(result: dict[str, Any], n: int, duration_s: float) -> None:
    """Print the rows as a table (rich if available)."""
    cells = [
        (r["backend"], f"{r['generation_s']:.2f}", f"{r['rollouts_per_s']:.2f}")
        for r in result["rows"]
    ]
    title = (
        f"simulator fit: generation of {n} x {duration_s:g} s NAO walks "
        f"({result['simulated_s_per_rollout']:.1f} s simulated each; "
        f"pool start-up {result['pool_startup_s']:.1f} s)"
    )
    print_table(
        title,
        ("backend", "generation (s)", "rollouts / s"),
        cells,
        justify=("left", "right", "right"),
    )


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--candidates", type=int, default=12)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    result = measure(args.candidates, args.duration, args.workers, args.repeats)
    show(result, args.candidates, args.duration)
    if args.json is not None:
        info = {"mujoco": mujoco.__version__, **environment()}
        write_json(
            args.json, {"args": vars(args) | {"json": str(args.json)}, "env": info, **result}
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
