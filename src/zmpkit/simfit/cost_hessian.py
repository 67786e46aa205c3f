r"""The fit's cost near an optimum as a quadratic, and what it pins down with the others free.

Which parameters, and which combinations, the data pin down when every other parameter is
free to compensate.

Around the fitted values :math:`v`, with relative moves :math:`\delta_i = \Delta v_i / v_i`,

.. math:: c(\delta) \approx c_0 + g^\top \delta + \tfrac12 \delta^\top H \delta .

:func:`hessian_candidates` lists the moves that determine :math:`H` by central differences
with a relative step :math:`h`: each parameter alone by :math:`\pm h` (the 1-D profile),
and each pair together by :math:`(+h, +h)` and :math:`(-h, -h)` — :math:`2n + n(n-1)`
candidates, one batch. :func:`hessian_from_costs` then gives

.. math::
    H_{ii} = \frac{c_i^+ + c_i^- - 2 c_0}{h^2}, \qquad
    H_{ij} = \frac{c_{ij}^{++} + c_{ij}^{--} - c_i^+ - c_i^- - c_j^+ - c_j^- + 2 c_0}{2 h^2},

exact for a quadratic cost (the gradient cancels, so it needs no optimum). It is a secant
curvature on the scale :math:`h`, the scale the identifiability decision asks about.

The resolution of a parameter is the relative change that raises the cost by a visible
:math:`\Delta c`:

- *conditional* (the others held at the optimum, the 1-D profile):
  :math:`\delta_c^* = \sqrt{2 \Delta c / H_{ii}}`;
- *marginal* (the others re-fitted, i.e. free to compensate):
  :math:`\delta_m^* = \sqrt{2 \Delta c \, (H^{-1})_{ii}} \ge \delta_c^*`.

A fit of many parameters can only be asked for the marginal: two parameters that trade off
(two compliances in series, say) each have a sharp profile but move together along a valley
the cost hardly sees. :math:`H^{-1}` is formed from the eigen-decomposition
:math:`H = V \Lambda V^\top`; a direction along which a move of 100 % raises the cost by
less than :math:`\Delta c` (:math:`\lambda_k < 2 \Delta c`, flat or concave ones included)
is *floppy* and counted as free over ±100 %, so

.. math:: (\delta_m^*)^2 = \sum_{k \,\text{stiff}} \frac{2 \Delta c\, V_{ik}^2}{\lambda_k}
          + \sum_{k \,\text{floppy}} V_{ik}^2 ,

and a parameter lying wholly in floppy directions reads 100 % (reported as infinite: no
visible rise within ±100 %). :func:`sloppy_directions` lists the directions whose own
resolution :math:`\sqrt{2 \Delta c / \lambda_k}` is coarser than a given limit, with their
components: the combinations the data leave loose.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "CostDirection",
    "conditional_resolutions",
    "hessian_candidates",
    "hessian_from_costs",
    "marginal_resolutions",
    "n_hessian_candidates",
    "sloppy_directions",
]


@dataclass(frozen=True)
class CostDirection:
    r"""A direction of the relative parameter space and how finely the data see it.

    Attributes:
        curvature: the Hessian's eigenvalue :math:`\lambda_k` along it [-].
        resolution: relative move along it that raises the cost by :math:`\Delta c`,
            :math:`\sqrt{2 \Delta c / \lambda_k}` [-] (inf: flat or concave).
        components: (parameter, component) of the unit eigenvector, largest first; the
            sign is chosen so the largest component is positive.
    """

    curvature: float
    resolution: float
    components: tuple[tuple[str, float], ...]


def n_hessian_candidates(n: int) -> int:
    """How many candidates :func:`hessian_candidates` lists for ``n`` parameters."""
    return 2 * n + n * (n - 1)


def hessian_candidates(
    values: Sequence[float] | NDArray[np.float64], step: float
) -> list[NDArray[np.float64]]:
    """The moved candidates [units], in the order :func:`hessian_from_costs` reads.

    Per parameter ×(1 − h), ×(1 + h); then per pair i < j both ×(1 + h), both ×(1 − h).
    """
    base = np.asarray(values, dtype=float)
    n = base.size
    out = []
    for i in range(n):
        for sign in (-1.0, 1.0):
            moved = base.copy()
            moved[i] *= 1.0 + sign * step
            out.append(moved)
    for i in range(n):
        for j in range(i + 1, n):
            for sign in (1.0, -1.0):
                moved = base.copy()
                moved[i] *= 1.0 + sign * step
                moved[j] *= 1.0 + sign * step
                out.append(moved)
    return out


def hessian_from_costs(
    costs: Sequence[float], cost_opt: float, n: int, step: float
) -> NDArray[np.float64]:
    """The Hessian :math:`H` [-] in relative coordinates (module docstring).

    ``costs`` are those of :func:`hessian_candidates`, in its order.

    A non-finite cost (a candidate whose rollout failed beyond the failure cost) makes the
    entries it enters NaN.
    """
    c = np.asarray(costs, dtype=float)
    if c.size != n_hessian_candidates(n):
        raise ValueError(f"expected {n_hessian_candidates(n)} costs for {n} parameters")
    minus, plus = c[0 : 2 * n : 2], c[1 : 2 * n : 2]
    h2 = step * step
    hessian = np.diag((plus + minus - 2.0 * cost_opt) / h2)
    k = 2 * n
    for i in range(n):
        for j in range(i + 1, n):
            both_plus, both_minus = c[k], c[k + 1]
            k += 2
            value = (
                both_plus + both_minus - plus[i] - minus[i] - plus[j] - minus[j] + 2.0 * cost_opt
            ) / (2.0 * h2)
            hessian[i, j] = hessian[j, i] = value
    return hessian


def conditional_resolutions(hessian: NDArray[np.float64], rise: float) -> NDArray[np.float64]:
    r"""Per parameter :math:`\sqrt{2 \Delta c / H_{ii}}` [-], the others held.

    Inf where :math:`H_{ii} \le 0`.
    """
    diag = np.diag(np.asarray(hessian, dtype=float))
    out = np.full(diag.shape, math.inf)
    positive = diag > 0.0
    out[positive] = np.sqrt(2.0 * rise / diag[positive])
    return out


def _eigen(hessian: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    h = np.asarray(hessian, dtype=float)
    if not np.all(np.isfinite(h)):
        raise ValueError("the Hessian has non-finite entries")
    return np.linalg.eigh(0.5 * (h + h.T))


def marginal_resolutions(hessian: NDArray[np.float64], rise: float) -> NDArray[np.float64]:
    r"""Per parameter the resolution with every other parameter free [-].

    :math:`\sqrt{2 \Delta c (H^{-1})_{ii}}` with floppy directions counted as free over
    ±100 % (module docstring); never below the conditional resolution; inf where it
    reaches 100 %.

    A Hessian with non-finite entries (a failed candidate) gives inf for every parameter.
    """
    n = np.asarray(hessian).shape[0]
    try:
        curvatures, vectors = _eigen(hessian)
    except ValueError:
        return np.full(n, math.inf)
    floor = 2.0 * rise  # lambda below which a 100 % move stays invisible
    weights = np.where(curvatures >= floor, 2.0 * rise / np.maximum(curvatures, floor), 1.0)
    squared = (vectors**2) @ weights
    marginal = np.sqrt(np.minimum(squared, 1.0))
    marginal = np.maximum(marginal, conditional_resolutions(hessian, rise))
    return np.where(marginal >= 1.0 - 1e-12, math.inf, marginal)


def sloppy_directions(
    hessian: NDArray[np.float64], rise: float, names: Sequence[str], coarser_than: float
) -> tuple[CostDirection, ...]:
    """The directions whose resolution is coarser than ``coarser_than`` [-], loosest first.

    Components smaller than 0.1 in magnitude are left out of :attr:`CostDirection.components`.
    An empty tuple when every direction is finer, or when the Hessian is not finite.
    """
    try:
        curvatures, vectors = _eigen(hessian)
    except ValueError:
        return ()
    out = []
    for k in np.argsort(curvatures):
        lam = float(curvatures[k])
        resolution = math.sqrt(2.0 * rise / lam) if lam > 0.0 else math.inf
        if resolution <= coarser_than:
            continue
        v = vectors[:, k]
        v = v if v[np.argmax(np.abs(v))] > 0 else -v
        order = np.argsort(-np.abs(v))
        components = tuple((names[i], float(v[i])) for i in order if abs(v[i]) >= 0.1)
        out.append(CostDirection(lam, resolution, components))
    return tuple(out)
