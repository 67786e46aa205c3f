r"""A fit's population and generations sized to the backend's width; IPOP restarts by budget.

A backend's *width* :math:`W` is how many candidates it evaluates in about the wall time of
one (:attr:`~zmpkit.simfit.backends.Evaluator.width`): 1 for the serial backend and for
MuJoCo Warp on a CPU, the threads of the local batches (each experiment one batch of every
candidate), the process pool's workers or a Ray cluster's CPUs divided among the
experiments (they run a task per candidate and experiment), :data:`WARP_GPU_WIDTH` on a
CUDA device. A generation of :math:`\lambda`
candidates costs :math:`\lceil \lambda / W \rceil` *batches* of wall time.

**Population.** Unless the user sets it, the first run's population is

.. math:: \lambda = \min(\max(\lambda_0, W), \lambda_{max}), \quad
          \lambda_0 = 4 + \lfloor 3 \ln n \rfloor

(:math:`\lambda_0` is ``cma``'s default for :math:`n` parameters): a population up to the
width costs a generation no more wall time than ``cma``'s default.

**Generations.** A larger population needs fewer generations. CMA-ES's progress per
generation grows about as :math:`\ln \lambda` once :math:`\lambda \gg n` (weighted
recombination of the :math:`\mu = \lambda/2` best), so a run with the population
:math:`\lambda` is given

.. math:: G(\lambda) = \lceil G_0 \, \ln \lambda_0 / \ln \lambda \rceil

generations, :math:`G_0` being the generations at :math:`\lambda_0` (``--generations``, or
the fit's default). Measured with ``cma`` on an ellipsoid (conditioning :math:`10^2`) and
Rosenbrock's function in [0, 1]^n, the median generations of 5 seeds to reach a cost of
:math:`10^{-8}` (``python benchmarks/bench_population.py``) fall from :math:`\lambda_0` to
256 by 3.6-4.0x for n = 2 and 2.6-3.4x for n = 12, where the rule predicts 3.1x and 2.3x,
and the rule gives at least the generations needed in 17 of its 18 cases (n = 2, 3, 12;
:math:`\lambda` = 64, 256, 1024); the exception, the 12-parameter ellipsoid at
:math:`\lambda = 64`, needed 119 generations where the rule gives 97. When the user sets the
population, each run has ``--generations`` generations, as they asked.

**IPOP restarts by budget** (``restarts`` None). The fit's wall-time budget is what its
first run would cost at :math:`\lambda_0`,

.. math:: B = G_0 \lceil \lambda_{ref} / W \rceil \text{ batches},

:math:`\lambda_{ref}` being the user's population or :math:`\lambda_0`. After a run stops
(its generations, or ``cma``'s own criteria), restart :math:`k` (population
:math:`2^k \lambda`, :mod:`~zmpkit.simfit.restarts`) runs when the budget left holds at least
half of its generations :math:`G(2^k\lambda)` at :math:`\lceil 2^k \lambda / W \rceil` batches
each, and runs as many of them as it holds. On a narrow backend the first run spends the
budget unless ``cma`` stops it early (then the rest goes to restarts); on a GPU
(:math:`W = 256`, :math:`n = 2`, :math:`G_0 = 30`) the first run of 256 takes 10 batches and
one restart of 512 another 18. An explicit ``restarts`` runs exactly that many, each with
the run's generations.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from zmpkit.errors import ParameterError
from zmpkit.simfit.cma_state import MAX_POPSIZE

__all__ = [
    "MIN_RESTART_SHARE",
    "WARP_GPU_WIDTH",
    "PopulationPlan",
    "batches",
    "cma_default_popsize",
    "generations_for",
    "population_plan",
]

MIN_RESTART_SHARE = 0.5
"""A restart by budget runs if the budget left holds this share of its generations."""

WARP_GPU_WIDTH = 256
"""Candidates a CUDA device evaluates in about one candidate's wall time on MuJoCo Warp.

Measured on an H200 (``benchmarks/bench_warp_fit.py``, a 10 s all-effects walk): 85 times
the candidates, 12 to 1024, cost 2.9 times the wall time; below ~500 worlds a step's launch
latency (0.68 ms), not the worlds, sets it."""


def cma_default_popsize(n: int) -> int:
    r"""``cma``'s default population for ``n`` parameters, :math:`4 + \lfloor 3 \ln n \rfloor`."""
    if n < 1:
        raise ParameterError(f"a fit needs at least one parameter; got {n}")
    return 4 + int(3 * math.log(n))


def generations_for(popsize: int, n: int, generations: int) -> int:
    r"""Generations of a run of ``popsize``: :math:`\lceil G_0 \ln\lambda_0 / \ln\lambda \rceil`.

    Args:
        popsize: the run's population :math:`\lambda`.
        n: the fitted parameters.
        generations: :math:`G_0`, the generations at ``cma``'s default population.

    Returns:
        ``generations`` for a population at most ``cma``'s default; fewer, at least 1, for a
        larger one.
    """
    default = cma_default_popsize(n)
    if popsize <= default:
        return generations
    return max(1, math.ceil(generations * math.log(default) / math.log(popsize)))


def batches(popsize: int, width: int) -> int:
    r"""Batches (wall-time units) of a generation: :math:`\lceil \lambda / W \rceil`."""
    return -(-popsize // width)


@dataclass(frozen=True)
class PopulationPlan:
    r"""How a fit uses its backend: population, generations per run, restarts.

    Attributes:
        width: candidates the backend evaluates in about the wall time of one.
        popsize: the first run's population.
        generations: :math:`G_0`, the generations at ``cma``'s default population (with a
            population the user set: every run's generations).
        scaled: runs get :math:`G(\lambda)` generations (the population was not set).
        restarts: IPOP restarts the user asked for; None = as many as ``budget`` allows.
        budget: the fit's wall-time budget in batches (with ``restarts`` None).
        n: the fitted parameters.
    """

    width: int
    popsize: int
    generations: int
    scaled: bool
    restarts: int | None
    budget: int
    n: int

    def run_generations(self, popsize: int) -> int:
        """Generations of a run of ``popsize`` candidates."""
        if not self.scaled:
            return self.generations
        return generations_for(popsize, self.n, self.generations)

    def run_cap(self, restart: int, popsize: int, spent_popsizes: Sequence[int]) -> int:
        """Generations of run ``restart`` (0 the first) of ``popsize``, within the budget.

        Args:
            restart: the run.
            popsize: its population.
            spent_popsizes: the population of every generation before the run began.
        """
        full = self.run_generations(popsize)
        if restart == 0 or self.restarts is not None:
            return full
        spent = sum(batches(p, self.width) for p in spent_popsizes)
        return max(0, min(full, (self.budget - spent) // batches(popsize, self.width)))

    def may_restart(self, restart: int, next_popsize: int, spent_popsizes: Sequence[int]) -> bool:
        """Whether restart number ``restart`` (1 the first) runs, with ``next_popsize``.

        With restarts by budget, a restart runs when the budget left holds at least half of
        its generations (:data:`MIN_RESTART_SHARE`); it then runs as many as the budget holds.

        Args:
            restart: the restart that would start.
            next_popsize: its population.
            spent_popsizes: the population of every generation run so far.
        """
        if next_popsize > MAX_POPSIZE:
            return False
        if self.restarts is not None:
            return restart <= self.restarts
        cap = self.run_cap(restart, next_popsize, spent_popsizes)
        return cap >= math.ceil(MIN_RESTART_SHARE * self.run_generations(next_popsize))


def population_plan(
    n: int,
    width: int,
    generations: int,
    popsize: int | None = None,
    restarts: int | None = None,
) -> PopulationPlan:
    """The plan of a fit of ``n`` parameters on a backend of ``width`` (module docstring).

    Args:
        n: the fitted parameters.
        width: the backend's width (>= 1).
        generations: :math:`G_0` (``--generations`` or the fit's default).
        popsize: the user's population; None sizes it to the backend.
        restarts: the user's IPOP restarts; None fills the budget.

    Raises:
        ParameterError: on a width or generations below 1.
    """
    if width < 1:
        raise ParameterError(f"a backend's width must be >= 1; got {width}")
    if generations < 1:
        raise ParameterError(f"generations must be >= 1; got {generations}")
    default = cma_default_popsize(n)
    first = popsize if popsize is not None else min(max(default, width), MAX_POPSIZE)
    reference = popsize if popsize is not None else default
    return PopulationPlan(
        width=width,
        popsize=first,
        generations=generations,
        scaled=popsize is None,
        restarts=restarts,
        budget=generations * batches(reference, width),
        n=n,
    )
