r"""Which parameters the data pin down.

Three measures per fitted parameter, all stated in the output, from one batch of
:math:`2n + n(n-1)` candidates around the optimum (:mod:`~zmpkit.simfit.cost_hessian`)
and a few more that measure the cost's roughness:

- **Profile** (conditional): the cost level at the optimum ``c0`` (below) and with one parameter
  moved by :math:`\pm h` (:data:`PROFILE_STEP`, relative), the others held. A parabola
  through the three points, :math:`c(\delta) \approx c_0 + a \delta^2`, gives the relative
  change that raises the cost by :math:`\Delta c = \Delta_{abs} + \Delta_{rel} c_0`
  (:data:`PROFILE_RISE_ABS`, :data:`PROFILE_RISE_REL`: 10 % above the residual misfit the
  data's noise and the unmodelled effects leave, and at least a 1 % mismatch of one term):

  .. math:: \delta^* = \sqrt{\Delta c / a}.

  A flat or concave profile gives :math:`\delta^* = \infty`.
- **The cost's local roughness** sets a floor under :math:`\Delta c`: a walk's cost is not
  smooth on small scales (a contact a frame earlier changes the rest of the walk), and in a
  self-test the hidden truth replays its recording exactly, an isolated spike far below its
  neighbours. :data:`ROUGHNESS_PROBES` candidates moved at random by
  :data:`ROUGHNESS_STEP` (relative, seeded) measure it: their spread :math:`s_r` (1.4826 ×
  the median absolute deviation) is the noise of the cost, and the level :math:`c_r` the
  profile and the Hessian are taken from is the centre's cost unless that lies more than
  :data:`ROUGHNESS_RISE` :math:`s_r` below their median (a spike; then that median less the
  margin): :math:`\Delta c = \max(\Delta_{abs} + \Delta_{rel} c_r,\;`
  :data:`ROUGHNESS_RISE` :math:`\, s_r)`. On a smooth cost this changes nothing.
- **Marginal** (the decision): the same rise with every other parameter free to
  compensate, from the cost's Hessian :math:`H` (pairs moved together by :math:`\pm h`):
  :math:`\delta_m^* = \sqrt{2 \Delta c (H^{-1})_{ii}} \ge \delta^*`. Parameters that trade
  off against each other (two compliances in series) each have a sharp profile and a
  coarse marginal; :attr:`Identifiability.sloppy` names the combinations the data leave
  loose.
- **CMA-ES spread**: the strategy's final standard deviation :math:`\sigma \sqrt{C_{ii}}`
  in normalised coordinates (a fraction of the bounds' range, of the log range for
  log-scaled parameters), converted to a relative spread of the value. It shrinks only
  once CMA-ES has converged, so after a short fit it is an upper bound.

A parameter is *identifiable* when its marginal resolution and its CMA-ES spread are both
within :data:`IDENTIFIABLE_WITHIN`. The marginal assumes the cost is quadratic over ±h; a
cost that rises like a cone (as :math:`|\delta|`, not :math:`\delta^2`: a walk with every
effect on, around its truth) costs less for two parameters moved together than the sum of
each, which reads as negative curvature along combined moves; those count as loose, so the
marginal is then pessimistic as the profile is optimistic, and the two bracket the truth.
A local measure alone is fooled by a rugged cost: a
walk is sensitive enough that a parameter moved 10 % from a local minimum raises the cost
steeply even where the search never settled (the walking robot's torso CoM x in a quick
self-test: a sharp profile, a 54 % CMA-ES spread, 76 % off).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.backends import Evaluator
from zmpkit.simfit.cost_hessian import (
    CostDirection,
    conditional_resolutions,
    hessian_candidates,
    hessian_from_costs,
    marginal_resolutions,
    sloppy_directions,
)
from zmpkit.simfit.problem import FitProblem

__all__ = [
    "IDENTIFIABLE_WITHIN",
    "PROFILE_RISE_ABS",
    "PROFILE_RISE_REL",
    "PROFILE_STEP",
    "ROUGHNESS_PROBES",
    "ROUGHNESS_RISE",
    "ROUGHNESS_STEP",
    "Identifiability",
    "ParameterIdentifiability",
    "identifiability",
    "local_level",
    "roughness_candidates",
    "visible_rise",
]

PROFILE_STEP = 0.10
"""Relative step of the 1-D cost profile and of the Hessian's pairs [-]."""
PROFILE_RISE_ABS = 1e-4
"""Absolute cost rise that counts as a visible misfit: one term off by 1 % [-]."""
PROFILE_RISE_REL = 0.10
"""Cost rise, relative to the optimum's cost, that counts as a visible misfit [-]."""
IDENTIFIABLE_WITHIN = 0.10
"""A parameter pinned down to this relative change or better is identifiable [-]."""
ROUGHNESS_STEP = 0.005
"""Relative size of the random moves that measure the cost's local roughness [-]."""
ROUGHNESS_PROBES = 12
"""How many random moves measure it (at least this, or one per parameter) [-]."""
ROUGHNESS_RISE = 2.0
"""A visible rise is at least this many times the cost's local scatter [-]."""


@dataclass(frozen=True)
class ParameterIdentifiability:
    r"""How well the data pin one parameter down.

    Attributes:
        name: the parameter.
        value: fitted value [unit].
        cost_minus: cost with the value × (1 − h) [-].
        cost_opt: cost at the fitted values [-].
        cost_plus: cost with the value × (1 + h) [-].
        resolution: relative change :math:`\delta^*` that raises the cost visibly, the
            others held (the profile) [-].
        cma_relative_std: CMA-ES's final spread as a fraction of the value [-]; NaN where
            the fitted values are not CMA-ES's (a refinement's end,
            :mod:`~zmpkit.simfit.least_squares_refit`), which has no spread.
        identifiable: marginal resolution and CMA-ES spread (where there is one) ≤
            :data:`IDENTIFIABLE_WITHIN`.
        marginal_resolution: the same with every other parameter free to compensate,
            :math:`\delta_m^*` [-] (inf: no visible rise within ±100 %).
    """

    name: str
    value: float
    cost_minus: float
    cost_opt: float
    cost_plus: float
    resolution: float
    cma_relative_std: float
    identifiable: bool
    marginal_resolution: float = math.nan

    @property
    def reason(self) -> str:
        """Why the parameter is identifiable or not, with the numbers that decided it."""
        within = f"{100 * IDENTIFIABLE_WITHIN:g} %"
        marginal = self.marginal_resolution
        if not math.isfinite(marginal):
            held = (
                ""
                if not math.isfinite(self.resolution)
                else (f" ({100 * self.resolution:.2g} % with the others held)")
            )
            return f"no visible cost rise within ±100 % with the others re-fitted{held}"
        spread = (
            f"CMA-ES spread {100 * self.cma_relative_std:.2g} %"
            if math.isfinite(self.cma_relative_std)
            else "refined by Levenberg–Marquardt (no CMA-ES spread there)"
        )
        numbers = (
            f"the cost rises visibly at ±{100 * marginal:.2g} % with the others re-fitted "
            f"({100 * self.resolution:.2g} % held), {spread}"
        )
        if self.identifiable:
            both = "both within" if math.isfinite(self.cma_relative_std) else "within"
            return f"{numbers}: {both} {within}"
        if marginal > IDENTIFIABLE_WITHIN >= self.resolution:
            return f"{numbers}: the others compensate it beyond {within}"
        return f"{numbers}: beyond {within}"


@dataclass(frozen=True)
class Identifiability:
    r"""Every parameter's identifiability, and the combinations the data leave loose.

    Attributes:
        parameters: one entry per fitted parameter, in the fit's order.
        sloppy: directions of the relative parameter space coarser than
            :data:`IDENTIFIABLE_WITHIN`, loosest first.
        hessian: the cost's Hessian in relative coordinates [-].
        rise: the cost rise that counts as visible, :math:`\Delta c` [-].
        level: the cost level the profile and the Hessian are taken from, :math:`c_r` [-].
        roughness: the cost's scatter under tiny random moves, :math:`s_r` [-].
    """

    parameters: tuple[ParameterIdentifiability, ...]
    sloppy: tuple[CostDirection, ...]
    hessian: NDArray[np.float64]
    rise: float
    level: float = math.nan
    roughness: float = math.nan


def visible_rise(cost_opt: float, roughness: float = 0.0) -> float:
    """The cost rise that counts as visible at an optimum of cost ``cost_opt`` [-].

    At least :data:`ROUGHNESS_RISE` times the cost's local scatter ``roughness`` [-].
    """
    return max(PROFILE_RISE_ABS + PROFILE_RISE_REL * cost_opt, ROUGHNESS_RISE * roughness)


def roughness_candidates(values: NDArray[np.float64], seed: int = 0) -> list[NDArray[np.float64]]:
    """Candidates moved at random by :data:`ROUGHNESS_STEP` (relative, a random direction)."""
    rng = np.random.default_rng([seed, 11])
    base = np.asarray(values, dtype=float)
    out = []
    for _ in range(max(ROUGHNESS_PROBES, base.size)):
        direction = rng.normal(size=base.size)
        out.append(base * (1.0 + ROUGHNESS_STEP * direction / np.linalg.norm(direction)))
    return out


def local_level(cost_opt: float, probe_costs: NDArray[np.float64]) -> tuple[float, float]:
    """The cost level :math:`c_r` and the scatter :math:`s_r` around an optimum [-].

    :math:`s_r` is 1.4826 × the probes' median absolute deviation (the standard deviation
    of normal scatter). :math:`c_r` is ``cost_opt`` unless that lies more than
    :data:`ROUGHNESS_RISE` scatters below the probes' median (a spike: an exact replay),
    then the median less that margin.
    """
    c = np.asarray(probe_costs, dtype=float)
    median = float(np.median(c))
    spread = 1.4826 * float(np.median(np.abs(c - median)))
    return max(float(cost_opt), median - ROUGHNESS_RISE * spread), spread


def _relative_std(
    problem: FitProblem,
    unit_std: NDArray[np.float64],
    values: Sequence[float] | NDArray[np.float64],
) -> NDArray[np.float64]:
    """Each parameter's standard deviation relative to its value [-] (log scale: as is)."""
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
) -> Identifiability:
    """Profile every parameter and every pair around ``values``, and judge each parameter.

    ``unit_std`` is CMA-ES's final spread at ``values``, NaN where they are not CMA-ES's
    (then the marginal resolution judges alone).

    One batch of :math:`2n + n(n-1)` candidates and the roughness probes (module docstring).
    """
    n = len(values)
    moved = hessian_candidates(values, PROFILE_STEP)
    probes = roughness_candidates(np.asarray(values, dtype=float))
    rows = evaluator.costs(moved + probes)
    every = [problem.cost_of(row) for row in rows]
    costs, probe_costs = every[: len(moved)], np.array(every[len(moved) :])
    level, roughness = local_level(cost_opt, probe_costs)
    hessian = hessian_from_costs(costs, level, n, PROFILE_STEP)
    rise = visible_rise(level, roughness)
    conditional = conditional_resolutions(hessian, rise)
    marginal = marginal_resolutions(hessian, rise)
    spread = _relative_std(problem, unit_std, values)
    out = []
    for i, p in enumerate(problem.parameters):
        out.append(
            ParameterIdentifiability(
                p.name,
                float(values[i]),
                costs[2 * i],
                cost_opt,
                costs[2 * i + 1],
                float(conditional[i]),
                float(spread[i]),
                bool(
                    marginal[i] <= IDENTIFIABLE_WITHIN
                    and (math.isnan(spread[i]) or spread[i] <= IDENTIFIABLE_WITHIN)
                ),
                float(marginal[i]),
            )
        )
    names = [p.name for p in problem.parameters]
    sloppy = sloppy_directions(hessian, rise, names, IDENTIFIABLE_WITHIN)
    return Identifiability(tuple(out), sloppy, hessian, rise, level, roughness)
