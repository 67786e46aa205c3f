r"""Which experiments pin which parameters, before any is recorded: information from curvature.

A local design (the parameters' nominal values :math:`v_0` stand for the unknown robot):
every candidate experiment is recorded once from the nominal robot, and the fit's cost of
that one experiment is evaluated on one shared list of candidates around :math:`v_0`
(:func:`design_candidates`): the centre, the :math:`2n + n(n-1)` moves that give the
cost's Hessian (:mod:`~zmpkit.simfit.cost_hessian`, relative step
:data:`~zmpkit.simfit.identifiability.PROFILE_STEP`) and the roughness probes
(:func:`~zmpkit.simfit.identifiability.roughness_candidates`).

Because the fit's cost of a set :math:`S` of experiments is the mean of theirs, and every
experiment was evaluated on the *same* candidates, the cost of any set on those candidates
is exactly the mean of the experiments' cost vectors:

.. math:: c_S(v_k) = \frac{1}{|S|} \sum_{e \in S} c_e(v_k),

so the Hessian, the cost's level and roughness, the visible rise and each parameter's
conditional and marginal resolution of *any* set (:func:`judge_set`) follow from arithmetic,
with no further rollout, by the same rules a fit's identifiability is judged by
(:mod:`~zmpkit.simfit.identifiability`): a parameter is pinned when its marginal resolution
(every other parameter free to compensate) is within
:data:`~zmpkit.simfit.identifiability.IDENTIFIABLE_WITHIN`.

:func:`greedy_design` chooses the set to record: starting from none, it adds the experiment
that pins the most parameters, ties broken by the least :math:`\sum_i \ln \min(\delta_i, 1)`
(a D-optimality-like score on the resolutions, 100 % for a parameter left free), until no
experiment pins another parameter or tightens that product by :data:`MIN_GAIN`, or all are
taken. The prefixes are reported, so a user sees
what each added experiment buys.

This is local: it says what the experiments would show on a robot near the nominal values.
It does not replace the fit's own judgement on the recorded data.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.simfit.cost_hessian import (
    conditional_resolutions,
    hessian_candidates,
    hessian_from_costs,
    marginal_resolutions,
    n_hessian_candidates,
)
from zmpkit.simfit.identifiability import (
    IDENTIFIABLE_WITHIN,
    PROFILE_STEP,
    local_level,
    roughness_candidates,
    visible_rise,
)

__all__ = [
    "MIN_GAIN",
    "ExperimentCosts",
    "SetJudgement",
    "design_candidates",
    "greedy_design",
    "judge_set",
]


MIN_GAIN = math.log(1.1)
"""An added experiment that pins no further parameter must tighten the product of the
resolutions by 10 % (this on the log score) to be worth recording [-]."""


def design_candidates(values: Sequence[float] | NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """The shared candidates [units]: the centre, the Hessian's moves, the roughness probes."""
    centre = np.asarray(values, dtype=float)
    return [centre.copy(), *hessian_candidates(centre, PROFILE_STEP), *roughness_candidates(centre)]


@dataclass(frozen=True, eq=False)
class ExperimentCosts:
    """One candidate experiment's cost on every :func:`design_candidates` candidate.

    Attributes:
        name: the experiment's name.
        costs: its cost per candidate, in :func:`design_candidates`' order [-].
    """

    name: str
    costs: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class SetJudgement:
    """What a set of experiments pins down (module docstring).

    Attributes:
        experiments: the set's experiment names, in the order they were added.
        conditional: per parameter, the resolution with the others held [-] (inf: none).
        marginal: per parameter, the resolution with the others free [-] (inf: none).
        rise: the visible cost rise the resolutions are measured against [-].
        level: the cost's level at the centre [-].
        roughness: the cost's scatter under the roughness probes [-].
        hessian: the set's cost Hessian in relative moves [-], shape (n, n).
    """

    experiments: tuple[str, ...]
    conditional: tuple[float, ...]
    marginal: tuple[float, ...]
    rise: float
    level: float
    roughness: float
    hessian: NDArray[np.float64]

    @property
    def pinned(self) -> tuple[bool, ...]:
        """Per parameter: marginal resolution within ``IDENTIFIABLE_WITHIN``."""
        return tuple(m <= IDENTIFIABLE_WITHIN for m in self.marginal)

    @property
    def score(self) -> tuple[int, float]:
        r"""(parameters pinned, :math:`-\sum_i \ln \min(\delta_i, 1)`): larger is better."""
        spread = sum(math.log(min(m, 1.0)) for m in self.marginal)
        return sum(self.pinned), -spread


def judge_set(chosen: Sequence[ExperimentCosts], parameters: int) -> SetJudgement:
    """The resolutions of the set ``chosen`` of experiments (module docstring).

    Args:
        chosen: the experiments' cost vectors (at least one).
        parameters: n, the number of fitted parameters.
    """
    if not chosen:
        raise ValueError("a set of experiments needs at least one")
    costs = np.mean([np.asarray(e.costs, dtype=float) for e in chosen], axis=0)
    moves = n_hessian_candidates(parameters)
    if costs.size <= 1 + moves:
        raise ValueError(f"expected more than {1 + moves} costs for {parameters} parameters")
    centre, moved, probes = costs[0], costs[1 : 1 + moves], costs[1 + moves :]
    level, roughness = local_level(float(centre), probes)
    hessian = hessian_from_costs(moved, level, parameters, PROFILE_STEP)
    rise = visible_rise(level, roughness)
    return SetJudgement(
        tuple(e.name for e in chosen),
        tuple(float(x) for x in conditional_resolutions(hessian, rise)),
        tuple(float(x) for x in marginal_resolutions(hessian, rise)),
        rise,
        level,
        roughness,
        hessian,
    )


def greedy_design(
    experiments: Sequence[ExperimentCosts], parameters: int, most: int | None = None
) -> list[SetJudgement]:
    """The sets the greedy choice builds, one per experiment added (module docstring).

    Args:
        experiments: the candidate experiments.
        parameters: n, the number of fitted parameters.
        most: stop after this many experiments (None: when nothing improves).

    Returns:
        The judgement of each prefix of the chosen sequence; the last is the recommended set.
    """
    left = list(experiments)
    chosen: list[ExperimentCosts] = []
    out: list[SetJudgement] = []
    limit = len(left) if most is None else min(most, len(left))
    while left and len(chosen) < limit:
        trials = [(judge_set([*chosen, e], parameters), e) for e in left]
        best, pick = max(trials, key=lambda t: t[0].score)
        if out and not _better(best.score, out[-1].score):
            break
        chosen.append(pick)
        left.remove(pick)
        out.append(best)
    return out


def _better(new: tuple[int, float], old: tuple[int, float]) -> bool:
    """Whether ``new`` pins more parameters, or as many and tightens by :data:`MIN_GAIN`."""
    return new[0] > old[0] or (new[0] == old[0] and new[1] >= old[1] + MIN_GAIN)
