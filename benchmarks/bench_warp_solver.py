"""Benchmark of the constraint solver's settings on a MuJoCo Warp batch: accuracy and time.

Usage::

    python benchmarks/bench_warp_solver.py [--device cpu|cuda:0] [--duration S]
                                           [--threads N] [--json PATH]

One recorded walk of ``--duration`` seconds (10 s at 0.2 m/s by default; every effect on,
:mod:`long_walk`) is replayed by 8 candidates (the hidden truth scaled by 0.8-1.1, and the
nominal values) in one Warp batch per solver setting: MuJoCo Warp's default (100
iterations, tolerance 1e-8 raised to its float32 floor of 1e-6, 50 line-search
iterations), 1, 2 and 4 iterations, and tolerances 10 and 100 times looser. Against the
default, per setting: the largest relative change of a walking candidate's cost, the
largest change of an encoder [rad], of the ZMP [m] and of the trunk pitch [rad] over the
walk, whether the same candidates complete it, and the wall time per physics step of the
batch (model upload included) with its ratio to the default's. Reported, never asserted.
Without ``mujoco_warp`` it says so and exits 0.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from harness import base_parser, print_table, write_run
from long_walk import long_walk, long_walk_arguments

__all__ = ["SETTINGS", "main"]

SETTINGS: tuple[tuple[str, dict[str, Any]], ...] = (
    ("default", {}),
    ("iterations=1", {"iterations": 1}),
    ("iterations=2", {"iterations": 2}),
    ("iterations=4", {"iterations": 4}),
    ("tolerance=1e-5 (10x)", {"tolerance": 1e-5}),
    ("tolerance=1e-4 (100x)", {"tolerance": 1e-4}),
)
"""Solver settings compared (keywords of :class:`~zmpkit.sim.solver_settings.SolverSettings`)."""


def _max_abs(a: np.ndarray, b: np.ndarray) -> float:
    both = np.isfinite(a) & np.isfinite(b)
    return float(np.max(np.abs(a[both] - b[both]))) if np.any(both) else float("nan")


def measure(device: str, duration_s: float) -> dict[str, Any]:
    """Per setting: cost changes, signal changes and time per step against the default."""
    from zmpkit.sim.solver_settings import SolverSettings
    from zmpkit.simfit.cost import experiment_cost
    from zmpkit.simfit.warp_batched import simulate_batches_warp

    with tempfile.TemporaryDirectory() as tmp:
        case = long_walk(Path(tmp), duration_s)
    problem: Any = case.problem
    (experiment,) = problem.experiments
    truths = [problem.truth(list(c)) for c in case.candidates]
    nstep = round(float(experiment.signals.time_s[-1]) / 1e-3)  # about; reported per step
    runs = {}
    for name, options in SETTINGS:
        start = time.perf_counter()
        (signals,) = simulate_batches_warp(
            [experiment], truths, problem.sim_effects, device, SolverSettings(**options)
        )
        wall = time.perf_counter() - start
        costs = [experiment_cost(experiment.signals, s, problem.models_loads) for s in signals]
        runs[name] = (signals, costs, wall)
    base_signals, base_costs, base_wall = runs["default"]
    rows = []
    for name, (signals, costs, wall) in runs.items():
        rel, dq, dzmp, dtilt = [], [], [], []
        same = all(c.completed == b.completed for c, b in zip(costs, base_costs, strict=True))
        for s, b, c, bc in zip(signals, base_signals, costs, base_costs, strict=True):
            if c.completed < 1.0 or bc.completed < 1.0:
                continue
            total, base = c.total(problem.weights), bc.total(problem.weights)
            rel.append(abs(total - base) / base)
            dq.append(_max_abs(s.q_meas_rad, b.q_meas_rad))
            dzmp.append(_max_abs(s.zmp_m, b.zmp_m))
            dtilt.append(_max_abs(s.trunk_tilt_rad, b.trunk_tilt_rad))
        rows.append(
            {
                "setting": name,
                "walking": sum(c.completed == 1.0 for c in costs),
                "same_completions": same,
                "max_rel_cost_change": max(rel) if rel else float("nan"),
                "median_rel_cost_change": float(np.median(rel)) if rel else float("nan"),
                "max_encoder_change_rad": max(dq) if dq else float("nan"),
                "max_zmp_change_m": max(dzmp) if dzmp else float("nan"),
                "max_pitch_change_rad": max(dtilt) if dtilt else float("nan"),
                "wall_s": wall,
                "ms_per_step": 1e3 * wall / nstep,
                "time_ratio": wall / base_wall,
                "costs": [c.total(problem.weights) for c in costs],
            }
        )
    return {
        "rows": rows,
        "candidates": list(case.labels),
        "duration_s": duration_s,
        "device": device,
        "steps_about": nstep,
    }


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    args = long_walk_arguments(base_parser(__doc__.splitlines()[0]), argv)
    if args is None:
        return 0
    result = measure(args.device, args.duration)
    cells = [
        (
            r["setting"],
            f"{r['walking']}/{len(result['candidates'])}",
            "yes" if r["same_completions"] else "NO",
            f"{r['max_rel_cost_change']:.2e}",
            f"{r['median_rel_cost_change']:.2e}",
            f"{r['max_encoder_change_rad']:.2e}",
            f"{r['max_zmp_change_m']:.2e}",
            f"{r['max_pitch_change_rad']:.2e}",
            f"{r['ms_per_step']:.2f}",
            f"{r['time_ratio']:.2f}",
        )
        for r in result["rows"]
    ]
    print_table(
        f"solver settings on MuJoCo Warp ({args.device}): {len(result['candidates'])} "
        f"candidates x {args.duration:g} s walk, changes against the default",
        (
            "setting",
            "walk",
            "same falls",
            "max d cost",
            "median d cost",
            "max d enc (rad)",
            "max d zmp (m)",
            "max d pitch (rad)",
            "ms/step",
            "time / default",
        ),
        cells,
    )
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
