r"""Does the fitted model explain the data? The best cost against the noise floor.

An estimate and its interval mean something only if the model, at its best, reproduces the
recording as well as the recording reproduces itself. The **noise floor** is that: the cost
the fitted model reaches against *itself*, recorded again with fresh sensor noise.

1. The fitted truth runs every experiment as the fit's rollouts do (the fit's sensor
   readings): the signals :math:`y_{fit}`; their cost against the recording is the best
   cost :math:`c^*`.
2. :data:`ADEQUACY_REPLICAS` replicas: the fitted truth with the sensors' *specification*
   (the base truth's noise, quantisation, offsets, filter: the sampled chain whatever the
   fit's readings) records every experiment again, noise seed
   :data:`REPLICA_SEED` + k — a virtual repetition of the experiment on a robot that *is*
   the fitted model. A walk with feedback reacts to that noise as the robot did, so its
   floor holds the noise's propagation through the closed loop, not only the sensors'.
   A walk-log window's replica starts a little before the window, from the state measured
   there, so the floor also holds the shooting's start-state error
   (:mod:`~zmpkit.simfit.shooting_window`).
   Each replica's cost :math:`c_k` is that of :math:`y_{fit}` against the replica, the
   recording's place; :math:`\bar c` and :math:`s_c` are their mean and standard deviation.
3. The model **explains the data** when

   .. math:: c^* \le \max(\rho\,\bar c,\; \bar c + 3 s_c)

   with :math:`\rho` = :data:`ADEQUATE_RATIO`: a correct model's :math:`c^*` is distributed
   as the :math:`c_k` (the recording is one more replica), or lower (the fit adapts to its
   noise).
4. **Residual structure**: the lag-1 autocorrelation :math:`r` of the joint residual
   :math:`q_{fit} - q_{rec}` (mean over joints and experiments), beside those of the
   replicas' residuals :math:`r_k` (mean :math:`\bar r`, standard deviation :math:`s_r`); a
   model that misses a dynamic leaves residuals smoother (closer to 1) than the noise does.
   The recording is one more replica if the model is right, so its :math:`r` lies below the
   one-sided 99 % prediction bound of a new draw from the :math:`K` replicas,

   .. math:: r \le \bar r + t_{0.99,\,K-1}\, s_r \sqrt{1 + 1/K},

   (Student's t with the replicas' :math:`K - 1` degrees of freedom); above it the residuals
   are **structured** and the model does not explain the data, whatever the cost says (a
   closed-loop walk's floor is high, its cost can hide a missing dynamic that its residuals
   show). Judged with at least two replicas.

When the model does not explain the data, the misfit, not the noise, shapes the cost
around the optimum: its intervals say how the misfit moves, not how precisely the robot's
value is known.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.stats import t as student_t

from zmpkit.simfit.cost import experiment_cost
from zmpkit.simfit.problem import FitProblem, simulate
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.shooting_window import replica_experiment
from zmpkit.simfit.truth_doc import load_robot_truth, truth_doc_with

__all__ = [
    "ADEQUACY_REPLICAS",
    "ADEQUATE_RATIO",
    "REPLICA_SEED",
    "Adequacy",
    "lag1_autocorrelation",
    "model_adequacy",
    "replica_recordings",
]

ADEQUACY_REPLICAS = 4
"""Replicas of every experiment that measure the noise floor [-]."""
ADEQUATE_RATIO = 2.0
"""A best cost up to this times the noise floor is explained by the noise [-]."""
REPLICA_SEED = 7919
"""Noise seed of the first replica (the k-th: + k); far from the seeds walks are recorded
with and from the fit's own [-]."""


@dataclass(frozen=True)
class Adequacy:
    r"""The model-adequacy check (module docstring).

    Attributes:
        best_cost: :math:`c^*`, the fitted model's cost against the recording [-].
        noise_floor: :math:`\bar c`, its mean cost against its own replicas [-].
        floor_std: :math:`s_c` [-] (NaN with fewer than two replicas).
        replicas: replicas that completed every experiment (a replica that falls is left
            out) [-].
        residual_lag1: lag-1 autocorrelation of the joint residual against the recording [-].
        floor_residual_lag1: the same against the replicas, their mean [-].
        floor_residual_lag1_std: their standard deviation [-] (NaN with fewer than two).
    """

    best_cost: float
    noise_floor: float
    floor_std: float
    replicas: int
    residual_lag1: float
    floor_residual_lag1: float
    floor_residual_lag1_std: float = math.nan

    @property
    def ratio(self) -> float:
        r""":math:`c^* / \bar c` [-] (inf on a zero floor)."""
        if self.noise_floor > 0.0:
            return self.best_cost / self.noise_floor
        return math.inf if self.best_cost > 0.0 else 1.0

    @property
    def limit(self) -> float:
        r"""The largest best cost the noise explains, :math:`\max(\rho \bar c, \bar c + 3 s_c)`."""
        spread = 0.0 if math.isnan(self.floor_std) else self.floor_std
        return max(ADEQUATE_RATIO * self.noise_floor, self.noise_floor + 3.0 * spread)

    @property
    def lag1_limit(self) -> float:
        r"""The largest :math:`r` a right model leaves (module docstring, 4) [-]; NaN unjudged."""
        spread = self.floor_residual_lag1_std
        if self.replicas < 2 or not math.isfinite(spread):
            return math.nan
        t = float(student_t.ppf(0.99, self.replicas - 1))
        return self.floor_residual_lag1 + t * spread * math.sqrt(1.0 + 1.0 / self.replicas)

    @property
    def structured(self) -> bool | None:
        """Whether the residuals are smoother than the noise leaves them; None unjudged."""
        limit = self.lag1_limit
        if not (math.isfinite(limit) and math.isfinite(self.residual_lag1)):
            return None
        return bool(self.residual_lag1 > limit)

    @property
    def judged(self) -> bool:
        """Whether a floor was measured (at least one replica completed)."""
        return self.replicas > 0 and math.isfinite(self.noise_floor)

    @property
    def explains(self) -> bool | None:
        """Whether the model explains the data; None when no floor was measured."""
        if not self.judged:
            return None
        return bool(self.best_cost <= self.limit) and self.structured is not True

    @property
    def verdict(self) -> str:
        """One line: the check's outcome and its numbers."""
        floor = f"noise floor {self.noise_floor:.3g}"
        if not math.isnan(self.floor_std):
            floor += f" ± {self.floor_std:.2g}"
        if self.explains is None:
            return "model adequacy not judged: every replica of the fitted model fell"
        numbers = (
            f"best cost {self.best_cost:.3g} = {self.ratio:.2g} × the {floor} "
            f"({self.replicas} replicas of the fitted model with fresh sensor noise)"
        )
        if self.explains:
            return f"the model explains the data: {numbers}"
        if self.best_cost > self.limit:
            why = f"{numbers}, above {self.limit:.3g}"
        else:
            why = (
                f"its residuals are smoother than the noise leaves them (lag-1 "
                f"autocorrelation {self.residual_lag1:.3g} against {self.floor_residual_lag1:.3g}"
                f" ± {self.floor_residual_lag1_std:.2g} of the replicas, above "
                f"{self.lag1_limit:.3g}: a dynamic the model misses), though its {numbers}"
            )
        return (
            f"the model does not explain the data: {why}; the intervals show how the misfit "
            "moves, not a precision"
        )


def lag1_autocorrelation(residual: NDArray[np.float64]) -> float:
    r""":math:`\sum r_t r_{t-1} / \sum r_t^2` per column, averaged over columns with energy.

    Args:
        residual: ``(N, J)`` residuals [any unit]; NaN where no column has energy.
    """
    r = np.asarray(residual, dtype=float)
    if r.ndim == 1:
        r = r[:, None]
    energy = np.sum(r * r, axis=0)
    ok = energy > 0.0
    if r.shape[0] < 2 or not np.any(ok):
        return math.nan
    lagged = np.sum(r[1:] * r[:-1], axis=0)
    return float(np.mean(lagged[ok] / energy[ok]))


def _mean_cost(
    problem: FitProblem, recorded: list[RecordedSignals], fitted: Sequence[RecordedSignals]
) -> float:
    """The fit's cost [-] of the fitted simulations against the recorded experiments (pooled)."""
    return problem.cost_of(
        [
            experiment_cost(rec, sim, problem.models_loads)
            for rec, sim in zip(recorded, fitted, strict=True)
        ]
    )


def _lag1(recorded: list[RecordedSignals], fitted: list[RecordedSignals]) -> float:
    values = [
        lag1_autocorrelation(sim.q_meas_rad - rec.q_meas_rad)
        for rec, sim in zip(recorded, fitted, strict=True)
        if sim.time_s.size == rec.time_s.size
    ]
    finite = [v for v in values if math.isfinite(v)]
    return float(np.mean(finite)) if finite else math.nan


def replica_recordings(
    problem: FitProblem, values: NDArray[np.float64], replicas: int = ADEQUACY_REPLICAS
) -> list[list[RecordedSignals]]:
    """The fitted model's replicas of every experiment (module docstring, step 2).

    Returns:
        Per replica that completed every experiment, its signals per experiment (a replica
        that fell or diverged in one is left out).
    """
    vals = np.asarray(values, dtype=float).tolist()
    truth = load_robot_truth(
        problem.robot, truth_doc_with(problem.base_doc, problem.parameters, vals)
    )
    out = []
    for k in range(replicas):
        replica = [
            simulate_experiment(
                replica_experiment(x, k), truth, problem.sim_effects, noise_seed=REPLICA_SEED + k
            )
            for x in problem.experiments
        ]
        recorded = [x.signals for x in problem.experiments]
        if all(r.time_s.size >= x.time_s.size for r, x in zip(replica, recorded, strict=True)):
            out.append(replica)
    return out


def model_adequacy(
    problem: FitProblem,
    values: NDArray[np.float64],
    replicas: int = ADEQUACY_REPLICAS,
    recordings: list[list[RecordedSignals]] | None = None,
) -> Adequacy:
    """The model-adequacy check of the fit at ``values`` [units] (module docstring).

    Runs ``1 + replicas`` rollouts of every experiment in this process (1 with
    ``recordings``: the replicas of :func:`replica_recordings`, already made).
    """
    vals = np.asarray(values, dtype=float).tolist()
    fitted = [simulate(problem, vals, e) for e in range(len(problem.experiments))]
    recorded = [x.signals for x in problem.experiments]
    best = _mean_cost(problem, recorded, fitted)
    if recordings is None:
        recordings = replica_recordings(problem, values, replicas)
    costs = [_mean_cost(problem, replica, fitted) for replica in recordings]
    lags = [_lag1(replica, fitted) for replica in recordings]
    floor = float(np.mean(costs)) if costs else math.nan
    spread = float(np.std(costs, ddof=1)) if len(costs) > 1 else math.nan
    finite = [v for v in lags if math.isfinite(v)]
    floor_lag = float(np.mean(finite)) if finite else math.nan
    lag_spread = float(np.std(finite, ddof=1)) if len(finite) > 1 else math.nan
    return Adequacy(best, floor, spread, len(costs), _lag1(recorded, fitted), floor_lag, lag_spread)
