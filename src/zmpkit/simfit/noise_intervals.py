r"""95 % intervals set by the data's noise: a linearised parametric bootstrap.

The adequacy check's replicas (:func:`~zmpkit.simfit.adequacy.replica_recordings`) are
:math:`K` recordings the robot could have given had it been the fitted model: the same
experiments, fresh sensor noise (through the closed loop, for a walk with feedback).
Fitting each again would give the estimates' scatter. To first order, in relative
coordinates :math:`\delta_i = \Delta v_i / v_i` about the fit :math:`v`, the re-fit of
replica :math:`k` moves the estimate by

.. math:: \delta_k = -H^{-1} g_k ,

with :math:`g_k` the gradient of replica :math:`k`'s cost at the fit, by central differences
over :math:`\pm h` (:data:`~zmpkit.simfit.identifiability.PROFILE_STEP`; the :math:`2n` moved
rollouts are shared by every replica), and :math:`H` the cost's Hessian at the fit
(:mod:`~zmpkit.simfit.cost_hessian`, the identifiability's). Every parameter re-fitted:
this is the profile with the others free, to second order (a quadratic cost's profile is
its marginal), with its threshold set by the noise instead of a chosen rise. The
replicas scatter about the fitted model, so :math:`\delta` has mean zero and parameter
:math:`i`'s relative half-width is

.. math:: w_i = t_{0.975,K} \sqrt{\tfrac1K \textstyle\sum_k \delta_{k,i}^2}

(Student's :math:`t` with :math:`K` degrees of freedom: four replicas make it 2.78 standard
deviations). A Hessian that is not positive definite (a loose direction) or a moved rollout
that falls leaves the interval unmeasured (NaN). The interval is a precision only when the
model explains the data (:mod:`~zmpkit.simfit.adequacy`): otherwise the misfit, not the
noise, moves the estimate.

It holds the noise, not the estimator's bias: a walk log's windows start from measured
states with the unmeasured ones at zero, which moves the estimate whatever the noise, and
these replicas (replays of the *data's* commands from the *data's* states) do not go
through that start-state estimation themselves. Where the data's pipeline can be run again
(a ``zmpkit walk`` log) the fit gives :mod:`~zmpkit.simfit.refit_intervals` instead.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.stats import t as student_t

from zmpkit.simfit.cost import experiment_cost
from zmpkit.simfit.identifiability import PROFILE_STEP
from zmpkit.simfit.problem import FitProblem, simulate
from zmpkit.simfit.recorded import RecordedSignals

__all__ = ["CONFIDENCE", "NoiseInterval", "linearised_shifts", "noise_intervals"]

CONFIDENCE = 0.95
"""Two-sided confidence of the intervals [-]."""


@dataclass(frozen=True)
class NoiseInterval:
    """One parameter's 95 % interval from the noise (module docstring).

    Attributes:
        name: the parameter.
        value: the fitted value [unit].
        half_width: relative half-width :math:`w_i` [-]; NaN when not measured.
        replicas: replicas it was measured from [-].
    """

    name: str
    value: float
    half_width: float
    replicas: int

    @property
    def bias(self) -> float:
        """The estimator's relative bias [-]: NaN, not estimated."""
        return math.nan

    @property
    def moves(self) -> tuple[float, ...]:
        """The replicas' relative moves [-]: not kept (only their spread)."""
        return ()

    @property
    def kind(self) -> str:
        """``noise_only``."""
        return "noise_only"

    @property
    def corrected(self) -> float:
        """The interval's centre [unit]: the fitted value (no bias is estimated)."""
        return self.value

    @property
    def lower(self) -> float:
        """Lower end [unit] (NaN when not measured)."""
        return self.value * (1.0 - self.half_width)

    @property
    def upper(self) -> float:
        """Upper end [unit] (NaN when not measured)."""
        return self.value * (1.0 + self.half_width)

    @property
    def method(self) -> str:
        """What the interval is, in words."""
        return (
            f"noise only: {self.replicas} replicas of the fitted model with fresh sensor noise,"
            " re-fitted to first order; the estimator's bias is not in it"
        )

    def covers(self, value: float) -> bool:
        """Whether ``value`` [unit] lies in the interval (False when not measured)."""
        return bool(self.lower <= value <= self.upper)


def linearised_shifts(
    hessian: NDArray[np.float64], gradients: NDArray[np.float64]
) -> NDArray[np.float64] | None:
    r"""The re-fits' relative moves :math:`-H^{-1} g_k`, one row per gradient.

    Returns:
        ``(K, n)`` moves [-], or None when :math:`H` is not positive definite (or not finite).
    """
    h = np.asarray(hessian, dtype=float)
    if not np.all(np.isfinite(h)):
        return None
    try:
        factor = np.linalg.cholesky(0.5 * (h + h.T))
    except np.linalg.LinAlgError:
        return None
    g = np.atleast_2d(np.asarray(gradients, dtype=float))
    return -np.linalg.solve(factor.T, np.linalg.solve(factor, g.T)).T


def _mean_cost(
    problem: FitProblem, recorded: list[RecordedSignals], simulated: Sequence[RecordedSignals]
) -> float:
    """The fit's cost [-] of ``simulated`` against the recorded experiments (pooled)."""
    return problem.cost_of(
        [
            experiment_cost(r, s, problem.models_loads)
            for r, s in zip(recorded, simulated, strict=True)
        ]
    )


def noise_intervals(
    problem: FitProblem,
    values: NDArray[np.float64],
    hessian: NDArray[np.float64],
    recordings: list[list[RecordedSignals]],
    step: float = PROFILE_STEP,
) -> tuple[NoiseInterval, ...]:
    """Every parameter's 95 % interval (module docstring); ``2n`` rollouts per experiment.

    Args:
        problem: the fit problem.
        values: the fitted values [units].
        hessian: the cost's Hessian at ``values``, relative coordinates [-].
        recordings: the replicas, per replica per experiment.
        step: the relative step :math:`h` of the central differences [-].
    """
    base = np.asarray(values, dtype=float)
    n, k = base.size, len(recordings)
    moved: list[list[RecordedSignals]] = []
    for i in range(n):
        for sign in (-1.0, 1.0):
            v = base.copy()
            v[i] *= 1.0 + sign * step
            moved.append(
                [simulate(problem, v.tolist(), e) for e in range(len(problem.experiments))]
            )
    gradients = np.array(
        [
            [
                (
                    _mean_cost(problem, rec, moved[2 * i + 1])
                    - _mean_cost(problem, rec, moved[2 * i])
                )
                / (2.0 * step)
                for i in range(n)
            ]
            for rec in recordings
        ]
    ).reshape(k, n)
    fell = any(
        s.time_s.size < x.signals.time_s.size
        for row in moved
        for s, x in zip(row, problem.experiments, strict=True)
    )
    shifts = linearised_shifts(hessian, gradients) if k > 0 and not fell else None
    half = np.full(n, math.nan)
    if shifts is not None and np.all(np.isfinite(shifts)):
        half = float(student_t.ppf(0.5 + CONFIDENCE / 2.0, k)) * np.sqrt(np.mean(shifts**2, axis=0))
    return tuple(
        NoiseInterval(p.name, float(base[i]), float(half[i]), k)
        for i, p in enumerate(problem.parameters)
    )
