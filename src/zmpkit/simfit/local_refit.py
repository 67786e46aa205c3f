r"""A small local re-fit: every parameter re-fitted from a nearby start (Nelder–Mead).

A replica of the data (:mod:`~zmpkit.simfit.pipeline_replicas`) is re-fitted from the fit
:math:`v` it was recorded from, and a profile point from the neighbouring one: both start
within a few percent of their optimum, where a population method would waste its
evaluations. The re-fit works in relative coordinates :math:`u_i = (x_i - v_i) / s_i`,
:math:`s_i = |v_i|` (the parameter's range where :math:`v_i = 0`, an offset), so every
parameter moves by the same relative step, and minimises the mean experiment cost

.. math:: C(u) = \frac1E \sum_e c_e\big(v + s \odot u\big)

by Nelder–Mead from the simplex :math:`\{0, s\,e_1, \dots, s\,e_n\}` with
:math:`s` = :data:`REFIT_STEP`: derivative-free, so the cost's small jumps (a contact's
timing moves the ZMP term at 0.3 % steps) do not stall it as they would a gradient. It stops
when the simplex is within :data:`REFIT_TOLERANCE` of its best vertex or after
:data:`REFIT_EVALUATIONS_PER_PARAMETER` :math:`\times n` evaluations. The values are held
inside their bounds. Every evaluation runs every experiment once in this process.

It finds the minimum of the basin it starts in. Where the cost has several minima along a
valley (a walk log's P gain against its gear stiffness: a re-fit of the data started at the
hidden truth (0.665, 1320 N·m/rad) stopped at (0.659, 1311), while CMA-ES found (0.676,
1199) with a lower cost), it does not follow the global fit's jumps between them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import minimize

from zmpkit.simfit.problem import FitProblem, evaluate

__all__ = [
    "REFIT_EVALUATIONS_PER_PARAMETER",
    "REFIT_STEP",
    "REFIT_TOLERANCE",
    "LocalRefit",
    "local_minimum",
    "local_refit",
    "mean_cost",
    "relative_values",
]

REFIT_STEP = 0.03
"""Relative size of the starting simplex [-]: about the estimator's bias on a walk log
(2.6–4.3 % on the gear stiffness of two held-out truths)."""
REFIT_TOLERANCE = 0.002
"""The simplex's relative size at which the re-fit stops [-]: below the cost's roughness
the minimum is not defined more finely."""
REFIT_EVALUATIONS_PER_PARAMETER = 30
"""Most cost evaluations per re-fitted parameter [-]."""


@dataclass(frozen=True)
class LocalRefit:
    """The outcome of one local re-fit.

    Attributes:
        values: the re-fitted values [units].
        cost: their cost [-].
        evaluations: cost evaluations spent [-].
    """

    values: tuple[float, ...]
    cost: float
    evaluations: int


def mean_cost(problem: FitProblem, values: Sequence[float]) -> float:
    """:math:`C`: the fit's cost [-] of ``problem``'s experiments at ``values``.

    Their mean, the logs' windows by their median (:mod:`~zmpkit.simfit.pooled_cost`).
    """
    terms = [evaluate(problem, values, e) for e in range(len(problem.experiments))]
    return problem.cost_of(terms)


def local_minimum(
    cost: Callable[[NDArray[np.float64]], float],
    n: int,
    step: float = REFIT_STEP,
    tolerance: float = REFIT_TOLERANCE,
    max_evaluations: int | None = None,
) -> tuple[NDArray[np.float64], float, int]:
    """Nelder–Mead on ``cost`` over ``u`` in :math:`R^n` from 0 (module docstring).

    Returns:
        The best ``u`` [-], its cost, and the evaluations spent.
    """
    simplex = np.vstack([np.zeros(n), step * np.eye(n)])
    result = minimize(
        cost,
        np.zeros(n),
        method="Nelder-Mead",
        options={
            "initial_simplex": simplex,
            "xatol": tolerance,
            "fatol": math.inf,
            "maxfev": max_evaluations or REFIT_EVALUATIONS_PER_PARAMETER * n,
        },
    )
    return np.asarray(result.x, dtype=float), float(result.fun), int(result.nfev)


def relative_values(
    problem: FitProblem, start: Sequence[float]
) -> Callable[[NDArray[np.float64]], list[float]]:
    r"""``u`` [-] to the values :math:`v + s \odot u` [units] (module docstring), in bounds."""
    v = np.asarray(start, dtype=float)
    lower = np.array([p.lower for p in problem.parameters], dtype=float)
    upper = np.array([p.upper for p in problem.parameters], dtype=float)
    scale = np.where(v != 0.0, np.abs(v), upper - lower)

    def values(u: NDArray[np.float64]) -> list[float]:
        return np.clip(v + scale * np.asarray(u, dtype=float), lower, upper).tolist()

    return values


def local_refit(
    problem: FitProblem, start: Sequence[float], step: float = REFIT_STEP
) -> LocalRefit:
    """Re-fit every parameter of ``problem`` from ``start`` [units] (module docstring)."""
    values = relative_values(problem, start)
    u, cost, spent = local_minimum(lambda u: mean_cost(problem, values(u)), len(start), step)
    return LocalRefit(tuple(values(u)), cost, spent)
