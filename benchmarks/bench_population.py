r"""Generations CMA-ES needs against its population: the basis of the fit's :math:`G(\lambda)`.

Usage::

    python benchmarks/bench_population.py [--dims 2,3,12] [--sizes 64,256,1024]
                                          [--seeds 5] [--target 1e-8] [--json PATH]

:mod:`zmpkit.simfit.population` gives a run of population :math:`\lambda` the generations
:math:`G(\lambda) = \lceil G_0 \ln\lambda_0 / \ln\lambda \rceil`. This measures, with
``cma`` in [0, 1]^n as the fit uses it (bounds, initial step 0.2, start at 0.5), the median
over ``--seeds`` of the generations to reach a cost below ``--target`` on two functions:

- an ellipsoid centred at 0.37 with axis weights :math:`100^{i/(n-1)}` (conditioning
  :math:`10^2`), the shape of a fit's cost near its minimum;
- Rosenbrock's function on [-2, 2]^n (a curved valley), the shape of a parameter trade-off.

Printed per function and dimension: the generations at ``cma``'s default population
:math:`\lambda_0` and at each ``--sizes``, their ratio to :math:`\lambda_0`'s, and the ratio
the rule predicts, :math:`\ln\lambda / \ln\lambda_0`. The rule is safe where the measured
ratio is at least the predicted one (it then gives at least as many generations as needed).
No simulation; reported, never asserted.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import cma
import numpy as np

from harness import base_parser, print_table, write_run
from zmpkit.simfit.population import cma_default_popsize

__all__ = ["ellipsoid", "generations_to_target", "main", "rosenbrock"]

MAX_GENERATIONS = 5000


def ellipsoid(x: np.ndarray) -> float:
    """Axis-weighted squares about 0.37, weights 100^(i/(n-1)) [-]."""
    z = np.asarray(x) - 0.37
    n = z.size
    weights = 100.0 ** (np.arange(n) / max(n - 1, 1))
    return float(np.sum(weights * z**2))


def rosenbrock(x: np.ndarray) -> float:
    """Rosenbrock's function of 4 (x - 0.5), minimum 0 at x = 0.75 [-]."""
    z = 4.0 * (np.asarray(x) - 0.5)
    return float(np.sum(100.0 * (z[1:] - z[:-1] ** 2) ** 2 + (1.0 - z[:-1]) ** 2))


def generations_to_target(
    f: Callable[[np.ndarray], float], n: int, popsize: int, seed: int, target: float
) -> int:
    """Generations until a candidate's cost is below ``target`` (at most 5000)."""
    options = {
        "popsize": popsize,
        "bounds": [0.0, 1.0],
        "seed": seed,
        "verbose": -9,
        "tolfun": 0.0,
        "tolx": 0.0,
        "tolfunhist": 0.0,
    }
    es = cma.CMAEvolutionStrategy(n * [0.5], 0.2, options)
    for generation in range(1, MAX_GENERATIONS + 1):
        candidates = es.ask()
        costs = [f(np.asarray(c)) for c in candidates]
        es.tell(candidates, costs)
        if min(costs) < target:
            return generation
    return MAX_GENERATIONS


def main(argv: list[str] | None = None) -> int:
    parser = base_parser(__doc__.splitlines()[0])
    parser.add_argument("--dims", default="2,3,12", help="parameter counts n")
    parser.add_argument("--sizes", default="64,256,1024", help="populations besides cma's")
    parser.add_argument("--seeds", type=int, default=5, help="seeds per case (median)")
    parser.add_argument("--target", type=float, default=1e-8, help="cost to reach")
    args = parser.parse_args(argv)
    dims = [int(d) for d in args.dims.split(",")]
    sizes = [int(s) for s in args.sizes.split(",")]
    rows, results = [], []
    for name, f in (("ellipsoid", ellipsoid), ("rosenbrock", rosenbrock)):
        for n in dims:
            default = cma_default_popsize(n)
            measured: dict[int, float] = {}
            for popsize in [default, *sizes]:
                runs = [
                    generations_to_target(f, n, popsize, seed, args.target)
                    for seed in range(1, args.seeds + 1)
                ]
                measured[popsize] = float(np.median(runs))
            for popsize in sizes:
                ratio = measured[default] / measured[popsize]
                rule = math.log(popsize) / math.log(default)
                rows.append(
                    [
                        name,
                        str(n),
                        f"{default}: {measured[default]:.0f}",
                        f"{popsize}: {measured[popsize]:.0f}",
                        f"{ratio:.2f}",
                        f"{rule:.2f}",
                        "yes" if ratio >= rule else "no",
                    ]
                )
                results.append(
                    {
                        "function": name,
                        "n": n,
                        "default_popsize": default,
                        "default_generations": measured[default],
                        "popsize": popsize,
                        "generations": measured[popsize],
                        "measured_ratio": ratio,
                        "rule_ratio": rule,
                    }
                )
    print_table(
        f"Median generations to a cost < {args.target:g} ({args.seeds} seeds)",
        [
            "function",
            "n",
            "λ0: generations",
            "λ: generations",
            "fewer (×)",
            "rule ln λ/ln λ0",
            "rule safe",
        ],
        rows,
    )
    out: dict[str, Any] = {"cases": results}
    write_run(args, out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
