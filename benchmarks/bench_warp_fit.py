r"""Benchmark of a fit generation: the ``warp`` backend against the CPU batch, same candidates.

Usage::

    python benchmarks/bench_warp_fit.py [--device cpu|cuda:0] [--candidates N]
                                        [--duration S] [--cpu-threads 2,16] [--calls C]
                                        [--json PATH]

The generation the issue's GPU targets are stated for: ``--candidates`` candidates of one
recorded ``--duration`` s NAO walk at 0.2 m/s with every effect on (:mod:`long_walk`),
drawn as in the middle of a fit (the hidden truth times :math:`e^{u}`, :math:`u \sim
N(0, 0.05^2)` per parameter, seed 0), evaluated by
:class:`~zmpkit.simfit.batch_backend.BatchEvaluator`, costs included. Measured in the same
run:

1. on MuJoCo Warp (``--device``): ``--calls`` generations; the first builds the Warp model,
   data and graphs (and loads the kernels from the persistent cache, or compiles them: run
   ``zmpkit warp warm-up`` first), the later ones reuse them (the fastest is the figure);
2. the host's share of a Warp generation, which no device removes: the candidates' fields
   written into one compiled model and their poses, as the backend builds them
   (:mod:`~zmpkit.simfit.candidate_worlds`); and, for comparison, what the path before it
   built: each candidate's truth and posed simulation (MJCF, compiled model, pose)
   (``benchmarks/bench_warp_host.py`` compares the two at 64 to 1024 candidates);
3. the CPU batch (the ``local`` backend) on each ``--cpu-threads`` count, the process pinned
   to that many CPUs (``all``: every CPU it may use), one generation each.

Printed: wall time per generation, candidates per second, the ratio of each CPU run to the
Warp generation (the targets: >= 5 at >= 1024 candidates against 16 cores; >= 1 at 12
candidates against 2 cores), and how far Warp's float32 costs are from the CPU's float64
ones (median and largest relative difference over the candidates that walk on both; the
candidates that fall on only one). The environment block has ``nvidia-smi``'s GPU line
where there is one, and Warp's device and memory high-water mark on CUDA. Reported, never
asserted. Without ``mujoco_warp`` it says so and exits 0.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import tempfile
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from harness import base_parser, pin_threads, print_table, write_run
from long_walk import long_walk, long_walk_arguments

__all__ = ["candidates_near", "main", "measure"]


def candidates_near(truth: Sequence[float], n: int, spread: float = 0.05) -> list[list[float]]:
    r"""``n`` candidates: the truth times :math:`e^{u}`, :math:`u \sim N(0, spread^2)`."""
    rng = np.random.default_rng(0)
    base = np.asarray(truth, dtype=float)
    return [list(base * np.exp(rng.normal(0.0, spread, base.size))) for _ in range(n)]


@contextlib.contextmanager
def _pinned(threads: int | None) -> Iterator[None]:
    """Run on ``threads`` CPUs (None: all this process may use), then restore the set."""
    before = os.sched_getaffinity(0)
    try:
        if threads is not None:
            pin_threads(threads)
        yield
    finally:
        os.sched_setaffinity(0, before)


def _gpu_line() -> str | None:
    """``nvidia-smi``'s name, driver and memory of each GPU, or None without one."""
    if shutil.which("nvidia-smi") is None:
        return None
    query = "--query-gpu=name,driver_version,memory.total,clocks.max.sm"
    done = subprocess.run(
        ["nvidia-smi", query, "--format=csv,noheader"], capture_output=True, text=True
    )
    return done.stdout.strip() or done.stderr.strip()


def _relative(warp: list[float], cpu: list[float]) -> dict[str, Any]:
    """Median and largest relative cost difference; candidates falling on one side only.

    A candidate falls (or diverges) when its cost is the failure cost (at least
    :data:`~zmpkit.simfit.cost.FAILED_COST`).
    """
    from zmpkit.simfit.cost import FAILED_COST

    fell_warp = [w >= FAILED_COST for w in warp]
    fell_cpu = [c >= FAILED_COST for c in cpu]
    walks = [i for i, (a, b) in enumerate(zip(fell_warp, fell_cpu, strict=True)) if not (a or b)]
    one_side = [i for i, (a, b) in enumerate(zip(fell_warp, fell_cpu, strict=True)) if a != b]
    rel = [abs(warp[i] - cpu[i]) / cpu[i] for i in walks]
    return {
        "walking": len(walks),
        "median": float(np.median(rel)) if rel else None,
        "max": float(np.max(rel)) if rel else None,
        "fall_on_one_side": one_side,
    }


def measure(
    device: str, ncandidates: int, duration_s: float, cpu_threads: Sequence[int | None], calls: int
) -> dict[str, Any]:
    """Every generation's wall time [s], the host share, and the cost differences."""
    from zmpkit.simfit.batch_backend import BatchEvaluator
    from zmpkit.simfit.candidate_worlds import CandidateValues, candidate_worlds
    from zmpkit.simfit.open_loop import posed_simulations, posed_world_simulations

    with tempfile.TemporaryDirectory() as tmp:
        case = long_walk(Path(tmp), duration_s)
    problem: Any = case.problem
    candidates = candidates_near(case.candidates[0], ncandidates)
    weights = problem.weights

    def totals(costs: list[list[Any]]) -> list[float]:
        return [sum(t.total(weights) for t in per) / len(per) for per in costs]

    warp = BatchEvaluator(problem, warp_device=device)
    warp_rows = []
    for call in range(calls):
        start = time.perf_counter()
        warp_costs = totals(warp.costs(candidates))
        warp_rows.append({"call": call + 1, "wall_s": time.perf_counter() - start})
    start = time.perf_counter()
    values = CandidateValues(
        problem.robot, problem.parameters, problem.simulated_base_doc, np.asarray(candidates)
    )
    posed_world_simulations(problem.experiments, candidate_worlds(values, problem.sim_effects))
    host_s = time.perf_counter() - start
    start = time.perf_counter()
    truths = [problem.truth(c) for c in candidates]
    posed_simulations(problem.experiments, truths, problem.sim_effects)
    compile_host_s = time.perf_counter() - start
    cpu_rows = []
    for threads in cpu_threads:
        with _pinned(threads):
            used = len(os.sched_getaffinity(0))
            start = time.perf_counter()
            cpu_costs = totals(BatchEvaluator(problem, threads=used).costs(candidates))
            wall = time.perf_counter() - start
        cpu_rows.append(
            {"threads": used, "wall_s": wall, "costs": _relative(warp_costs, cpu_costs)}
        )
    memory = None
    with contextlib.suppress(Exception):
        import warp as wp

        if wp.get_device(device or None).is_cuda:
            memory = wp.get_mempool_used_mem_high(device or None)
    return {
        "candidates": ncandidates,
        "duration_s": duration_s,
        "warp": warp_rows,
        "host_s": host_s,
        "compile_host_s": compile_host_s,
        "cpu": cpu_rows,
        "gpu": _gpu_line(),
        "warp_device": device or "default",
        "warp_memory_high_bytes": memory,
    }


def _threads(text: str) -> list[int | None]:
    return [None if t.strip() == "all" else int(t) for t in text.split(",") if t.strip()]


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print the tables, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--candidates", type=int, default=12)
    parser.add_argument("--cpu-threads", default="2,all", help="CPU runs, e.g. 2,16 or all")
    parser.add_argument("--calls", type=int, default=2, help="Warp generations (first builds)")
    args = long_walk_arguments(parser, argv)
    if args is None:
        return 0
    try:
        threads = _threads(args.cpu_threads)
    except ValueError:
        parser.error(f"--cpu-threads must be counts or 'all', e.g. 2,16; got {args.cpu_threads}")
    if args.candidates < 1 or args.calls < 1:
        parser.error("--candidates and --calls must be >= 1")
    result = measure(args.device, args.candidates, args.duration, threads, args.calls)
    best = min(r["wall_s"] for r in result["warp"][1:] or result["warp"])
    n = result["candidates"]
    cells = [
        (
            f"warp {result['warp_device']}, call {r['call']}",
            f"{r['wall_s']:.2f}",
            f"{n / r['wall_s']:.1f}",
            "",
            "",
        )
        for r in result["warp"]
    ]
    cells.append(("host share (fields, poses)", f"{result['host_s']:.2f}", "", "", ""))
    cells.append(
        ("host share, compiled (truths, models)", f"{result['compile_host_s']:.2f}", "", "", "")
    )
    for r in result["cpu"]:
        c = r["costs"]
        diff = (
            f"{100 * c['median']:.2f} / {100 * c['max']:.2f} ({c['walking']} walk)"
            if c["median"] is not None
            else "none walk"
        )
        if c["fall_on_one_side"]:
            diff += f"; fall on one side: {c['fall_on_one_side']}"
        cells.append(
            (
                f"cpu, {r['threads']} threads",
                f"{r['wall_s']:.2f}",
                f"{n / r['wall_s']:.1f}",
                f"{r['wall_s'] / best:.2f}",
                diff,
            )
        )
    print_table(
        f"fit generation: {n} candidates x one {args.duration:g} s walk, every effect"
        + (f"; GPU: {result['gpu']}" if result["gpu"] else ""),
        ("run", "wall (s)", "candidates/s", "cpu / warp", "cost d warp-cpu: median / max %"),
        cells,
        justify=("left", "right", "right", "right", "left"),
    )
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
