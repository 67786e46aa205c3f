"""Benchmark of finding a batch's per-world fields: vectorised against the per-model loop.

Usage::

    python benchmarks/bench_warp_fields.py [--sizes 64,1024,4096] [--distinct D]
                                           [--repeats R] [--json PATH]

A batch is a CMA-ES generation's candidate models of the virtual NAO (M, G and S on): ``D``
candidates are built as the fit builds them (a truth document with PID gain scale and gear
stiffness drawn in their bounds, then the robot's model), and copied round-robin up to each
size (the time does not depend on the values). Measured in the same run, best of
``--repeats``, for each size:

1. :func:`zmpkit.sim.warp_model._differing_fields`, vectorised (one look-up per dtype and
   model, one comparison against the first model per dtype);
2. the per-model, per-field loop it replaced (``tests/helpers/warp_reference.py``);
3. the per-world arrays of the differing fields (:func:`~zmpkit.sim.warp_model.per_world_values`).

Neither needs MuJoCo Warp (the batchable set is every field here, as the comparison is the
cost). Ratios are reported, never asserted.
"""

from __future__ import annotations

import copy
import sys
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from harness import base_parser, print_table, write_run
from zmpkit.robots.nao import make_nao
from zmpkit.robots.registry import get_robot
from zmpkit.sim.warp_model import _differing_fields, _model_arrays, per_world_values
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.truth_doc import (
    base_truth_path,
    load_robot_truth,
    load_truth_doc,
    truth_doc_with,
)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from helpers.warp_reference import reference_differing_fields

__all__ = ["main"]

EFFECTS = "M,G,S"


def candidates(distinct: int, size: int) -> list[mujoco.MjModel]:
    """``size`` candidate models: ``distinct`` built as the fit builds them, then copies."""
    params = default_parameters(get_robot("nao"), "M,G", ("pid_gain_scale", "gear_stiffness"))
    doc = load_truth_doc(base_truth_path(get_robot("nao"), None))
    rng = np.random.default_rng(0)
    built = []
    for _ in range(min(distinct, size)):
        values = [p.from_unit(float(rng.uniform(0.1, 0.9))) for p in params]
        truth = load_robot_truth(get_robot("nao"), truth_doc_with(doc, params, values))
        built.append(make_nao(EFFECTS, truth, seed=0).model)
    return [
        built[i] if i < len(built) else copy.deepcopy(built[i % len(built)]) for i in range(size)
    ]


def best_wall(run: Any, repeats: int) -> tuple[float, Any]:
    """Best wall time of ``run()`` over ``repeats`` calls [s], and its last result."""
    best, out = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - start)
    return best, out


def measure(sizes: list[int], distinct: int, repeats: int) -> dict[str, Any]:
    """Per size: walls of the vectorised and the reference search, and of the stacking [s]."""
    models = candidates(distinct, max(sizes))
    batchable = set(_model_arrays(models[0]))
    rows = []
    for size in sizes:
        batch = models[:size]
        new_s, fields = best_wall(lambda b=batch: _differing_fields(b, batchable), repeats)
        ref_s, ref = best_wall(lambda b=batch: reference_differing_fields(b, batchable), repeats)
        if fields != ref:
            raise AssertionError(f"different fields: {fields} vs {ref}")
        stack_s, _ = best_wall(lambda b=batch, f=fields: per_world_values(b, f), repeats)
        rows.append(
            {
                "models": size,
                "fields": list(fields),
                "vectorised_s": new_s,
                "per_model_loop_s": ref_s,
                "per_world_values_s": stack_s,
            }
        )
    return {"rows": rows}


def show(result: dict[str, Any]) -> None:
    """Print the rows as a table (rich if available)."""
    cells = [
        (
            str(r["models"]),
            f"{r['per_model_loop_s']:.3f}",
            f"{r['vectorised_s']:.3f}",
            f"{r['per_model_loop_s'] / r['vectorised_s']:.1f}x",
            f"{r['per_world_values_s']:.4f}",
        )
        for r in result["rows"]
    ]
    fields = ", ".join(result["rows"][0]["fields"])
    print_table(
        f"per-world fields of candidate models ({EFFECTS}); differing: {fields}",
        ("models", "per-model loop (s)", "vectorised (s)", "speed-up", "per-world arrays (s)"),
        cells,
        justify=("right", "right", "right", "right", "right"),
    )


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark, print a table, write JSON if asked; returns the exit status."""
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="64,1024,4096", help="batch sizes, comma separated")
    parser.add_argument("--distinct", type=int, default=32, help="candidates built, then copied")
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    result = measure(sizes, args.distinct, args.repeats)
    show(result)
    write_run(args, result)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
