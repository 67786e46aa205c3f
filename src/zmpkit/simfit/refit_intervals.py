r"""95 % intervals that hold the estimator's bias: re-fits of replicas through the pipeline.

The noise-only intervals (:mod:`~zmpkit.simfit.noise_intervals`) assume the estimate
scatters about the truth. A walk log's multiple shooting does not: its windows start from
measured states with the unmeasured ones at zero, and the estimate moves by a **bias**
:math:`b` that no noise seed removes (:mod:`~zmpkit.simfit.pipeline_replicas`). Model the
estimate of parameter :math:`i`, relative to a scale :math:`s_i` (:math:`|\hat\theta_i|`,
or the parameter's range where the estimate is zero), as

.. math:: \hat\theta = \theta + s\,(b + e), \qquad e \sim (0, \sigma^2),

with :math:`b` constant near the fit. Replica :math:`k` is the data's pipeline run on a
robot that *is* the fit :math:`\hat\theta` (recorded through the same sensors and window
start-state estimation, another noise seed) and re-fitted with every parameter free, by
CMA-ES as the data was (:mod:`~zmpkit.simfit.replica_refit`):
:math:`\hat\theta_k = \hat\theta + s(b + e_k)`. A log
``zmpkit walk`` wrote is walked again with its controller (:data:`PIPELINE_REFITS`,
:mod:`~zmpkit.simfit.pipeline_replicas`); any other log's windows are replayed again from
before their starts on the log's commands and re-cut from the replica's own sensors
(:data:`WINDOW_REFITS`, :mod:`~zmpkit.simfit.window_replicas`): they hold the start-state
estimation's bias but not a controller's answer to other noise.
Their relative moves :math:`\delta_k = (\hat\theta_k - \hat\theta) / s` estimate the bias
and the scatter,

.. math:: \hat b = \bar\delta, \qquad \hat\sigma^2 = \tfrac{1}{K-1}\textstyle\sum_k
          (\delta_k - \bar\delta)^2 .

The bias-corrected estimate :math:`\tilde\theta = \hat\theta - s\hat b = \theta + s(e - \bar e)`
has variance :math:`s^2\sigma^2 (1 + 1/K)`, so the 95 % interval is

.. math:: \hat\theta + s\left(-\hat b \pm t_{0.975,\,K-1}\,\hat\sigma\sqrt{1 + 1/K}\right)

(Student's :math:`t` with the replicas' :math:`K - 1` degrees of freedom). Nothing is
widened by a chosen factor: the width is the replicas' scatter, the shift their mean move.
Because every parameter is re-fitted in every replica, an interval is that of a profile
with the others re-fitted, and a trade-off between two parameters (a softer gear against a
stiffer servo) moves both together. A profile of the data's own cost could not do this: it
is centred on the biased minimum whatever threshold it is given.

It assumes the bias is the same at the fit as at the truth (it changes slowly with the
parameters) and that the replicas' robot differs from the real one only in the fitted
parameters; with fewer than two re-fitted replicas the interval is not measured (NaN).
Re-fitted by Nelder–Mead from the fit instead (:mod:`~zmpkit.simfit.local_refit`), the
replicas missed the estimator's jumps between the bumps of a flat valley: on five held-out
truths of the built-in walker (three walks each), 8 of 10 intervals covered the truth, both
misses a stiff gear fitted 9–10 % low. Re-fitted by CMA-ES, the same five truths' intervals
cover 10 of 10 walked again and 7 of 10 with the windows replayed again (their P intervals
about half as wide, their gear's mean move not the fit's error on one truth).
"""

from __future__ import annotations

import math
import multiprocessing
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.stats import t as student_t

from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.simfit.closed_loop import WalkSettings
from zmpkit.simfit.noise_intervals import CONFIDENCE, NoiseInterval
from zmpkit.simfit.pipeline_replicas import pipeline_replica, walk_settings
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.replica_refit import replica_refit
from zmpkit.simfit.window_replicas import replayable_windows, window_replica

__all__ = [
    "PIPELINE_REFITS",
    "REFIT_REPLICAS",
    "WINDOW_REFITS",
    "ParameterInterval",
    "RefitInterval",
    "interval_scales",
    "refit_intervals",
    "replica_estimate",
    "replica_intervals",
]

PIPELINE_REFITS = "pipeline_refits"
"""The kind of an interval from replicas walked again (:mod:`~zmpkit.simfit.pipeline_replicas`)."""
WINDOW_REFITS = "window_refits"
"""The kind of an interval from a log's windows replayed again
(:mod:`~zmpkit.simfit.window_replicas`)."""
REFIT_REPLICAS = 6
r"""Replicas recorded and re-fitted [-]: six make the interval
:math:`t_{0.975,5}\sqrt{7/6} = 2.78` scatters wide, four 3.56."""


@dataclass(frozen=True)
class RefitInterval:
    r"""One parameter's bias-corrected 95 % interval (module docstring).

    Attributes:
        name: the parameter.
        value: the fitted value :math:`\hat\theta` [unit].
        scale: :math:`s` [unit].
        moves: the replicas' relative moves :math:`\delta_k` [-].
    """

    name: str
    value: float
    scale: float
    moves: tuple[float, ...]
    kind: str = PIPELINE_REFITS

    @property
    def replicas(self) -> int:
        """Re-fitted replicas :math:`K` [-]."""
        return len(self.moves)

    @property
    def bias(self) -> float:
        r""":math:`\hat b`, the estimator's mean relative move [-]; NaN without replicas."""
        return float(np.mean(self.moves)) if self.moves else math.nan

    @property
    def spread(self) -> float:
        r""":math:`\hat\sigma` [-]; NaN with fewer than two replicas."""
        return float(np.std(self.moves, ddof=1)) if len(self.moves) > 1 else math.nan

    @property
    def half_width(self) -> float:
        r"""Relative half-width :math:`t_{0.975,K-1}\hat\sigma\sqrt{1+1/K}` [-] (NaN unmeasured)."""
        if self.replicas < 2 or not math.isfinite(self.spread):
            return math.nan
        t = float(student_t.ppf(0.5 + CONFIDENCE / 2.0, self.replicas - 1))
        return t * self.spread * math.sqrt(1.0 + 1.0 / self.replicas)

    @property
    def corrected(self) -> float:
        r"""The bias-corrected estimate :math:`\hat\theta - s\hat b` [unit]."""
        return self.value - self.scale * self.bias

    @property
    def lower(self) -> float:
        """Lower end [unit] (NaN when not measured)."""
        return self.corrected - self.scale * self.half_width

    @property
    def upper(self) -> float:
        """Upper end [unit] (NaN when not measured)."""
        return self.corrected + self.scale * self.half_width

    @property
    def method(self) -> str:
        """What the interval is, in words."""
        if self.kind == WINDOW_REFITS:
            return (
                f"bias-corrected: {self.replicas} replicas of the fitted model replaying the "
                "log's commands from before each window, the windows re-cut from their own "
                "sensors, each re-fitted; it holds the noise and the start-state estimation's "
                "bias as those replicas show them, not a controller's answer to other noise"
            )
        return (
            f"bias-corrected: {self.replicas} replicas of the fitted model walked again "
            "through the data's pipeline (controller, sensors, windows), each re-fitted; it "
            "holds the noise and the estimator's bias as those replicas show them"
        )

    def covers(self, value: float) -> bool:
        """Whether ``value`` [unit] lies in the interval (False when not measured)."""
        return bool(self.lower <= value <= self.upper)


ParameterInterval = NoiseInterval | RefitInterval
"""A fitted parameter's 95 % interval, either kind (its ``method`` says which)."""


def replica_intervals(
    names: Sequence[str],
    values: Sequence[float],
    scales: Sequence[float],
    estimates: NDArray,
    kind: str = PIPELINE_REFITS,
) -> tuple[RefitInterval, ...]:
    r"""Every parameter's interval from the replicas' re-fits (module docstring).

    Args:
        names: the parameters.
        values: the fit :math:`\hat\theta` [units].
        scales: :math:`s` [units].
        estimates: ``(K, n)`` re-fitted values :math:`\hat\theta_k` [units].
        kind: which replicas (:data:`PIPELINE_REFITS`, :data:`WINDOW_REFITS`).
    """
    v, s = np.asarray(values, dtype=float), np.asarray(scales, dtype=float)
    moves = (np.asarray(estimates, dtype=float).reshape(-1, v.size) - v) / s
    return tuple(
        RefitInterval(n, float(v[i]), float(s[i]), tuple(float(m) for m in moves[:, i]), kind)
        for i, n in enumerate(names)
    )


def interval_scales(parameters: Sequence[FitParameter], values: Sequence[float]) -> list[float]:
    """:math:`s`: ``|value|``, or the parameter's range where the value is zero [units]."""
    pairs = zip(parameters, values, strict=True)
    return [abs(v) if v != 0.0 else p.upper - p.lower for p, v in pairs]


def refit_intervals(
    problem: FitProblem,
    values: Sequence[float],
    replicas: int = REFIT_REPLICAS,
    progress: Callable[[int, int], None] | None = None,
    workers: int = 1,
) -> tuple[RefitInterval, ...] | None:
    """Every parameter's bias-corrected interval of the fit (module docstring).

    Runs ``replicas`` recorded walks per log and a local re-fit of each, on ``workers``
    processes (each replica is independent and seeded by its number, so any number of
    workers gives the same intervals).

    Args:
        problem: the fit problem.
        values: the fitted values [units].
        replicas: replicas to record and re-fit [-].
        progress: called with (replicas done, replicas) after each.
        workers: processes; 1 runs them in this process.

    Returns:
        The intervals: from walks recorded again when every experiment is a window of a
        log that ``zmpkit walk`` wrote with a feedback controller
        (:func:`~zmpkit.simfit.pipeline_replicas.walk_settings`), else from the windows
        replayed again when every experiment is a window of a walk log
        (:mod:`~zmpkit.simfit.window_replicas`); None otherwise.
    """
    settings = walk_settings(problem)
    if settings is None and not replayable_windows(problem):
        return None
    kind = WINDOW_REFITS if settings is None else PIPELINE_REFITS
    start = [float(v) for v in values]
    found: dict[int, tuple[float, ...] | None] = {}
    if workers <= 1 or replicas <= 1:
        for k in range(replicas):
            found[k] = replica_estimate(problem, start, k, settings)
            if progress is not None:
                progress(k + 1, replicas)
    else:
        context = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(min(workers, replicas), mp_context=context) as pool:
            futures = {
                pool.submit(replica_estimate, problem, start, k, settings): k
                for k in range(replicas)
            }
            for future in as_completed(futures):
                found[futures[future]] = future.result()
                if progress is not None:
                    progress(len(found), replicas)
    estimates = [found[k] for k in range(replicas) if found[k] is not None]
    names = [p.name for p in problem.parameters]
    scales = interval_scales(problem.parameters, values)
    return replica_intervals(names, values, scales, np.array(estimates), kind)


def replica_estimate(
    problem: FitProblem, values: list[float], k: int, settings: dict[str, WalkSettings] | None
) -> tuple[float, ...] | None:
    """Replica ``k`` recorded by the fit at ``values`` and re-fitted; None if it diverged.

    Walked again with ``settings``; None: the log's windows replayed again.
    """
    if settings is None:
        replica = window_replica(problem, values, k)
    else:
        replica = pipeline_replica(problem, values, k, settings)
    return None if replica is None else replica_refit(replica, values, k).values
