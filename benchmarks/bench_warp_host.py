r"""Benchmark of the host's share of a Warp generation: one compilation against one each.

Usage::

    python benchmarks/bench_warp_host.py [--sizes 64,256,1024] [--duration S]
                                         [--parameters quick,all] [--repeats R] [--json PATH]

The generation of ``benchmarks/bench_warp_fit.py``: candidates of one recorded NAO walk at
0.2 m/s with every effect on (:mod:`long_walk`), drawn around the hidden truth (the
truth times :math:`e^{u}`, :math:`u \sim N(0, 0.05^2)` per parameter, seed 0), for the
quick fit's two parameters (``quick``: PID gain scale, gear stiffness) and for the NAO's
whole catalogue (``all``: M, I, G, F, S and C, the torso's mass and CoM, whose derived
fields ``mj_setConst`` recomputes per candidate). Measured in the same run, best of
``--repeats``, for each size, what the host does before the device rollout:

1. **compile** (the path before issue 30, and the fallback): each candidate's truth, robot
   description, MJCF, compiled model and pose
   (:func:`~zmpkit.simfit.open_loop.posed_simulations`), then the comparison of the models
   and the stacking of their differing fields (what :func:`~zmpkit.sim.warp_batch.rollout_warp`
   does with a list of models);
2. **fields** (the default): one compiled model, each candidate's parameters written into
   its per-world fields (:func:`~zmpkit.simfit.candidate_worlds.candidate_worlds`), and
   each candidate posed on a host copy of it
   (:func:`~zmpkit.simfit.open_loop.posed_world_simulations`).

Neither needs MuJoCo Warp. Printed: seconds per generation (wall; and the process's CPU
time of the fields path, less sensitive to other processes on a shared machine),
milliseconds per candidate, the ratio compile / fields (wall). The target of issue 30:
fields <= 0.5 s at 1024 candidates.

With ``--warp-device`` (``cpu``: Warp's CPU device; needs ``mujoco_warp``), also a whole
generation of ``--warp-candidates`` candidates (quick parameters) through the fit's
evaluator (:class:`~zmpkit.simfit.batch_backend.BatchEvaluator`), twice (the first builds
the Warp model and loads the kernels): its wall time, the device rollout's
(:func:`~zmpkit.sim.warp_batch.rollout_warp`), the candidates' fields and poses, and the rest
of the host's work (reading the rows, the costs). Reported, never asserted.
"""

from __future__ import annotations

import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from bench_warp_fit import candidates_near
from harness import base_parser, print_table, write_run
from long_walk import long_walk

__all__ = ["main", "measure"]


def _best(run: Callable[[], Any], repeats: int) -> tuple[float, float]:
    """Best wall time and best CPU time of this process of ``run()`` over ``repeats`` [s]."""
    wall = cpu = float("inf")
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        run()
        wall = min(wall, time.perf_counter() - start)
        cpu = min(cpu, time.process_time() - start_cpu)
    return wall, cpu


def _problem(case: Any, which: str) -> tuple[Any, list[list[float]]]:
    """The fit problem with the ``quick`` or ``all`` parameters, and the truth's values."""
    from zmpkit.simfit.parameters import robot_catalogue
    from zmpkit.simfit.problem import FitProblem

    problem = case.problem
    if which == "quick":
        return problem, list(case.candidates[0])
    params = robot_catalogue(problem.robot)
    quick = {p.name: v for p, v in zip(problem.parameters, case.candidates[0], strict=True)}
    truth = [quick.get(p.name, p.nominal) for p in params]
    whole = FitProblem(problem.robot, problem.sim_effects, params, problem.base_doc,
                       problem.experiments)  # fmt: skip
    return whole, truth


def _compile_path(problem: Any, candidates: list[list[float]]) -> None:
    from zmpkit.sim.warp_model import _differing_fields, _model_arrays, per_world_values
    from zmpkit.simfit.open_loop import posed_simulations

    truths = [problem.truth(c) for c in candidates]
    sims = posed_simulations(problem.experiments, truths, problem.sim_effects)
    models = [s.model for per in sims for s in per]
    every = set(_model_arrays(models[0]))
    per_world_values(models, _differing_fields(models, every))


def _fields_path(problem: Any, candidates: list[list[float]]) -> None:
    from zmpkit.simfit.candidate_worlds import CandidateValues, candidate_worlds
    from zmpkit.simfit.open_loop import posed_world_simulations

    values = CandidateValues(
        problem.robot, problem.parameters, problem.simulated_base_doc, np.asarray(candidates)
    )
    worlds = candidate_worlds(values, problem.sim_effects)
    posed_world_simulations(problem.experiments, worlds)


def measure(
    sizes: list[int], duration_s: float, parameters: list[str], repeats: int
) -> dict[str, Any]:
    """Wall time of both paths per size and parameter set [s]."""
    with tempfile.TemporaryDirectory() as tmp:
        case = long_walk(Path(tmp), duration_s)
    rows = []
    for which in parameters:
        problem, truth = _problem(case, which)
        for n in sizes:
            candidates = candidates_near(truth, n)
            compile_s, compile_cpu = _best(
                lambda p=problem, c=candidates: _compile_path(p, c), repeats
            )
            fields_s, fields_cpu = _best(
                lambda p=problem, c=candidates: _fields_path(p, c), repeats
            )
            rows.append(
                {
                    "parameters": which,
                    "nparameters": len(problem.parameters),
                    "candidates": n,
                    "compile_s": compile_s,
                    "fields_s": fields_s,
                    "compile_cpu_s": compile_cpu,
                    "fields_cpu_s": fields_cpu,
                }
            )
    return {"duration_s": duration_s, "effects": case.problem.sim_effects, "rows": rows}


def warp_generation(case: Any, device: str, n: int, calls: int = 2) -> list[dict[str, float]]:
    """A generation of ``n`` candidates on MuJoCo Warp, ``calls`` times: where its time goes."""
    from zmpkit.sim import warp_batch
    from zmpkit.simfit import warp_batched
    from zmpkit.simfit.batch_backend import BatchEvaluator

    spent = {"device_s": 0.0, "fields_s": 0.0}

    def timed(function: Callable[..., Any], key: str) -> Callable[..., Any]:
        def run(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                spent[key] += time.perf_counter() - start

        return run

    originals = (
        warp_batch.rollout_warp,
        warp_batched.candidate_worlds,
        warp_batched.posed_world_simulations,
    )
    warp_batch.rollout_warp = timed(originals[0], "device_s")  # imported when called
    warp_batched.candidate_worlds = timed(originals[1], "fields_s")
    warp_batched.posed_world_simulations = timed(originals[2], "fields_s")
    try:
        evaluator = BatchEvaluator(case.problem, warp_device=device)
        candidates = candidates_near(case.candidates[0], n)
        rows = []
        for call in range(calls):
            spent.update(device_s=0.0, fields_s=0.0)
            start = time.perf_counter()
            evaluator.costs(candidates)
            wall = time.perf_counter() - start
            rest = wall - spent["device_s"] - spent["fields_s"]
            rows.append({"call": call + 1, "wall_s": wall, **spent, "rest_s": rest})
        return rows
    finally:
        warp_batch.rollout_warp = originals[0]
        warp_batched.candidate_worlds = originals[1]
        warp_batched.posed_world_simulations = originals[2]


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print the table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="64,256,1024", help="candidates per generation")
    parser.add_argument("--duration", type=float, default=1.5, help="walk duration [s]")
    parser.add_argument("--parameters", default="quick,all", help="quick, all, or both")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--warp-device", help="also a generation on this Warp device (cpu)")
    parser.add_argument("--warp-candidates", type=int, default=64)
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    which = [w.strip() for w in args.parameters.split(",") if w.strip()]
    if not sizes or min(sizes) < 1 or args.repeats < 1 or set(which) - {"quick", "all"}:
        parser.error("--sizes and --repeats must be >= 1; --parameters: quick and/or all")
    result = measure(sizes, args.duration, which, args.repeats)
    if args.warp_device is not None:
        with tempfile.TemporaryDirectory() as tmp:
            case = long_walk(Path(tmp), args.duration)
        rows = warp_generation(case, args.warp_device, args.warp_candidates)
        result["warp"] = {"device": args.warp_device, "candidates": args.warp_candidates}
        result["warp"]["calls"] = rows
    cells = [
        (
            f"{r['parameters']} ({r['nparameters']})",
            str(r["candidates"]),
            f"{r['compile_s']:.3f}",
            f"{r['fields_s']:.3f}",
            f"{r['fields_cpu_s']:.3f}",
            f"{1e3 * r['fields_s'] / r['candidates']:.3f}",
            f"{r['compile_s'] / r['fields_s']:.1f}",
        )
        for r in result["rows"]
    ]
    print_table(
        f"host share of a Warp generation: NAO walk, effects {result['effects']}",
        (
            "parameters",
            "candidates",
            "compile (s)",
            "fields (s)",
            "fields CPU (s)",
            "fields (ms/cand)",
            "ratio",
        ),
        cells,
        justify=("left", "right", "right", "right", "right", "right", "right"),
    )
    if "warp" in result:
        print_table(
            f"a generation on Warp ({result['warp']['device']}): "
            f"{result['warp']['candidates']} candidates, quick parameters",
            ("call", "wall (s)", "device rollout (s)", "fields, poses (s)", "rest of host (s)"),
            [
                (
                    str(r["call"]),
                    f"{r['wall_s']:.3f}",
                    f"{r['device_s']:.3f}",
                    f"{r['fields_s']:.3f}",
                    f"{r['rest_s']:.3f}",
                )
                for r in result["warp"]["calls"]
            ],
            justify=("left", "right", "right", "right", "right"),
        )
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
