r"""The re-fit of an interval replica: CMA-ES from the fit, searching as the data's fit did.

A replica's move (:mod:`~zmpkit.simfit.refit_intervals`) stands for the estimator's error
only if the replica is re-fitted the way the data was. A walk log's cost is flat along the
valley where a softer gear trades against a stiffer servo, and rough along it (a contact's
timing moves the ZMP term in small steps): measured on a 10 s ``zmpip`` walk of the built-in
walker (hidden P gain scale 0.797, gear 1424 N·m/rad; fit 0.808, 1324), the cost along the
line from the fit to the truth stays within 0.0062–0.0069 from 15 % softer to 11 % stiffer
gears, with bumps of 0.0005 between, and the truth itself on a bump (0.0079). The fit's
estimate is wherever CMA-ES found the lowest bump. A Nelder–Mead re-fit from the fit
(:mod:`~zmpkit.simfit.local_refit`) stays in the basin it starts in: six replicas of that
walk (:mod:`~zmpkit.simfit.window_replicas`) moved the gear by +2.6 % (standard deviation
1.4 %) and their interval, [1239, 1340] N·m/rad, missed the truth; re-fitted by this
search they moved it by −0.5 % (3.1 %), and the interval [1218, 1443] covers it.

The re-fit is CMA-ES in the relative coordinates of :mod:`~zmpkit.simfit.local_refit`,
:math:`u_i = (x_i - v_i) / s_i` from :math:`u = 0` (the fit :math:`v`), with step size
:data:`REPLICA_SIGMA`, ``cma``'s default population :math:`4 + \lfloor 3 \ln n \rfloor` and
:data:`REPLICA_GENERATIONS` generations; the values are held inside their bounds. Its
draws come from a generator seeded by the replica's number, so a replica re-fits the same
in any process. The estimate is the best point it evaluated, the fit's own included.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import cma
import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.local_refit import LocalRefit, mean_cost, relative_values
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.restarts import global_rng, set_global_rng

__all__ = ["REPLICA_GENERATIONS", "REPLICA_SIGMA", "cma_minimum", "replica_refit"]

REPLICA_SIGMA = 0.1
"""CMA-ES's initial step in relative units [-]: about the flat valley's half-extent along
the gear stiffness (its marginal resolution on the built-in walker's walk logs, 8–13 %)."""
REPLICA_GENERATIONS = 10
"""Generations of a replica's re-fit [-]: 60 evaluations for two parameters, the budget
Nelder–Mead was given (30 per parameter)."""


def cma_minimum(
    cost: Callable[[NDArray[np.float64]], float], n: int, seed: int
) -> tuple[NDArray[np.float64], float, int]:
    """CMA-ES on ``cost`` over ``u`` in :math:`R^n` from 0 (module docstring).

    Returns:
        The best ``u`` evaluated (0 included) [-], its cost, and the evaluations spent.
    """
    best_u, best, spent = np.zeros(n), float(cost(np.zeros(n))), 1
    draws = np.random.RandomState(seed)
    outer = global_rng()
    set_global_rng(np.random.RandomState(seed + 1).get_state())  # cma's draws beside randn
    try:
        options: dict[str, Any] = {"seed": np.nan, "randn": draws.randn, "verbose": -9}
        options["maxiter"] = REPLICA_GENERATIONS
        es = cma.CMAEvolutionStrategy(np.zeros(n).tolist(), REPLICA_SIGMA, options)
        while not es.stop():
            candidates = es.ask()
            costs = [float(cost(np.asarray(u, dtype=float))) for u in candidates]
            spent += len(costs)
            es.tell(candidates, [c if math.isfinite(c) else 1e300 for c in costs])
            k = int(np.argmin(costs))
            if costs[k] < best:
                best_u, best = np.asarray(candidates[k], dtype=float), costs[k]
    finally:
        set_global_rng(outer)
    return best_u, best, spent


def replica_refit(problem: FitProblem, start: Sequence[float], seed: int) -> LocalRefit:
    """Re-fit every parameter of ``problem`` from ``start`` [units] (module docstring).

    Args:
        problem: the replica's fit problem.
        start: the data's fit :math:`v` [units].
        seed: seeds the search's draws [-].
    """
    values = relative_values(problem, start)
    u, cost, spent = cma_minimum(lambda u: mean_cost(problem, values(u)), len(start), seed)
    return LocalRefit(tuple(values(u)), cost, spent)
