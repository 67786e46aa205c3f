r"""The ``cma`` strategy of a fit, its random draws, and IPOP-CMA-ES restarts.

``cma`` samples through its ``randn`` option, here a private ``RandomState``
(:attr:`~zmpkit.simfit.checkpoint.Checkpoint.draws`, whose state travels in the checkpoint);
any other draw it makes comes from numpy's global generator, whose state the checkpoint keeps
and :func:`with_rng` swaps in only around the strategy's calls.

IPOP-CMA-ES (Auger & Hansen 2005): when a run stops (``cma``'s own stop criteria, or its
generation budget, :func:`run_over`), :func:`restart` starts a new run from a uniformly
random mean in [0, 1]^n with the same initial step size and twice the previous population,

.. math:: \lambda_k = 2^k \lambda_0, \quad k = 0 \ldots \text{restarts},

and the fit keeps the best candidate over all runs. Restart k draws its mean and its samples
from a ``RandomState`` seeded by (seed, k), so a fit resumed in any run continues in that run
and ends as an uninterrupted one.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from zmpkit.simfit.checkpoint import Checkpoint
from zmpkit.simfit.cma_state import new_strategy

__all__ = [
    "global_rng",
    "new_strategy",
    "restart",
    "run_over",
    "set_global_rng",
    "unit_std",
    "with_rng",
]


def global_rng() -> Any:
    """Return NumPy's global random state (``cma`` may draw from it)."""
    return np.random.get_state()  # noqa: NPY002 - cma draws from the legacy global generator


def set_global_rng(state: Any) -> None:
    """Set NumPy's global random state."""
    np.random.set_state(state)  # noqa: NPY002 - cma draws from the legacy global generator


def with_rng(state: Checkpoint, call: Callable[[], Any]) -> Any:
    """Run ``call`` with the checkpoint's global random state swapped in, and keep its new one."""
    outer = global_rng()
    set_global_rng(state.rng_state)
    try:
        return call()
    finally:
        state.rng_state = global_rng()
        set_global_rng(outer)


def unit_std(strategy: Any) -> list[float]:
    r"""The strategy's standard deviation per coordinate, :math:`\sigma \sqrt{C_{ii}}` [-]."""
    return (float(strategy.sigma) * np.sqrt(np.diag(strategy.sm.covariance_matrix))).tolist()


def run_over(state: Checkpoint, generations: int) -> bool:
    """Whether the current run has stopped: ``generations`` of its own, or ``cma``'s criteria."""
    return state.generation - state.run_start >= generations or bool(state.strategy.stop())


def restart(state: Checkpoint, seed: int, sigma0: float) -> None:
    """Start the next IPOP run in ``state``: random mean, ``sigma0``, twice the population.

    The finished run's spread is kept when it found the best candidate so far.
    """
    if state.best_restart == state.restart:
        state.best_run_std = unit_std(state.strategy)
    state.restart += 1
    state.run_start = state.generation
    draws = np.random.RandomState([seed, state.restart])
    mean = draws.uniform(0.0, 1.0, len(state.best_unit))
    popsize = 2 * int(state.strategy.popsize)
    state.strategy = with_rng(state, lambda: new_strategy(mean, sigma0, popsize, draws))
    state.draws = draws
