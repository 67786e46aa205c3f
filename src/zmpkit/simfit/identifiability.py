r"""Which parameters the data pins down.

Two measures per fitted parameter, both stated in the output:

- **Profile** (the decision): the cost at the optimum ``c0`` and with that one parameter
  moved by :math:`\pm h` (:data:`PROFILE_STEP`, relative), the others held. A parabola
  through the three points, :math:`c(\delta) \approx c_0 + a \delta^2`, gives the relative
  change that raises the cost by :math:`\Delta c = \Delta_{abs} + \Delta_{rel} c_0`
  (:data:`PROFILE_RISE_ABS`, :data:`PROFILE_RISE_REL`: 10 % above the residual misfit the
  data's noise and the unmodelled effects leave, and at least a 1 % mismatch of one term):

  .. math:: \delta^* = \sqrt{\Delta c / a}.

  The data distinguish the parameter from a value 10 % off when :math:`\delta^* \le`
  :data:`IDENTIFIABLE_WITHIN` (10 %). A flat or concave profile gives
  :math:`\delta^* = \infty`.
- **CMA-ES spread**: the strategy's final standard deviation :math:`\sigma \sqrt{C_{ii}}`
  in normalised coordinates (a fraction of the bounds' range, of the log range for
  log-scaled parameters), converted to a relative spread of the value. It shrinks only
  once CMA-ES has converged, so after a short fit it is an upper bound.

A parameter is *identifiable* when both are within :data:`IDENTIFIABLE_WITHIN`. The profile
alone is fooled by a rugged cost: a walk is sensitive enough that a parameter moved 10 %
from a local minimum raises the cost steeply even where the search never settled (the
the walking robot's torso CoM x in a quick self-test: a sharp profile, a 54 % CMA-ES spread,
76 % off).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.backends import Evaluator
from zmpkit.simfit.problem import FitProblem

__all__ = [
    "IDENTIFIABLE_WITHIN",
    "PROFILE_RISE_ABS",
    "PROFILE_RISE_REL",
    "PROFILE_STEP",
    "ParameterIdentifiability",
    "identifiability",
]

PROFILE_STEP = 0.10
"""Relative step of the 1-D cost profile [-]."""
PROFILE_RISE_ABS = 1e-4
"""Absolute cost rise that counts as a visible misfit: one term off by 1 % [-]."""
PROFILE_RISE_REL = 0.10
"""Cost rise, relative to the optimum's cost, that counts as a visible misfit [-]."""
IDENTIFIABLE_WITHIN = 0.10
"""A parameter pinned down to this relative change or better is identifiable [-]."""


@dataclass(frozen=True)
class ParameterIdentifiability:
    r"""How well the data pin one parameter down.

    Attributes:
        name: the parameter.
        value: fitted value [unit].
        cost_minus: cost with the value × (1 − h) [-].
        cost_opt: cost at the fitted values [-].
        cost_plus: cost with the value × (1 + h) [-].
        resolution: relative change :math:`\delta^*` that raises the cost visibly [-].
        cma_relative_std: CMA-ES's final spread as a fraction of the value [-].
        identifiable: resolution and CMA-ES spread ≤ :data:`IDENTIFIABLE_WITHIN`.
    """

    name: str
    value: float
    cost_minus: float
    cost_opt: float
    cost_plus: float
    resolution: float
    cma_relative_std: float
    identifiable: bool


def _resolution(c_minus: float, c0: float, c_plus: float, h: float) -> float:
    curvature = (0.5 * (c_minus + c_plus) - c0) / (h * h)
    if not math.isfinite(curvature) or curvature <= 0.0:
        return math.inf
    return math.sqrt((PROFILE_RISE_ABS + PROFILE_RISE_REL * c0) / curvature)


def _relative_std(problem: FitProblem, unit_std: NDArray[np.float64], values) -> NDArray:
    out = []
    for p, s, v in zip(problem.parameters, unit_std, values, strict=True):
        if p.log_scale:
            out.append(float(s) * math.log(p.upper / p.lower))
        else:
            out.append(float(s) * (p.upper - p.lower) / max(abs(v), 1e-12))
    return np.array(out)


def identifiability(
    problem: FitProblem,
    evaluator: Evaluator,
    values: NDArray[np.float64],
    cost_opt: float,
    unit_std: NDArray[np.float64],
) -> tuple[ParameterIdentifiability, ...]:
    """Profile every parameter around ``values`` (2 n candidates, one batch) and judge it."""
    candidates = []
    for i in range(len(values)):
        for sign in (-1.0, 1.0):
            moved = np.array(values, dtype=float)
            moved[i] *= 1.0 + sign * PROFILE_STEP
            candidates.append(moved)
    rows = evaluator.costs(candidates)
    costs = [float(np.mean([t.total(problem.weights) for t in row])) for row in rows]
    spread = _relative_std(problem, unit_std, values)
    out = []
    for i, p in enumerate(problem.parameters):
        c_minus, c_plus = costs[2 * i], costs[2 * i + 1]
        resolution = _resolution(c_minus, cost_opt, c_plus, PROFILE_STEP)
        out.append(
            ParameterIdentifiability(
                p.name,
                float(values[i]),
                c_minus,
                cost_opt,
                c_plus,
                resolution,
                float(spread[i]),
                resolution <= IDENTIFIABLE_WITHIN and spread[i] <= IDENTIFIABLE_WITHIN,
            )
        )
    return tuple(out)
