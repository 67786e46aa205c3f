"""95 % intervals from the noise: against the exact re-fits of a linear model."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import t as student_t

from zmpkit.robots.registry import get_robot
from zmpkit.simfit import noise_intervals as module
from zmpkit.simfit.noise_intervals import NoiseInterval, linearised_shifts, noise_intervals
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.recorded import RecordedSignals


@settings(max_examples=50)
@given(st.integers(1, 5), st.integers(0, 2**32 - 1))
def test_linearised_shifts_solve_the_newton_step(n: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n))
    hessian = a @ a.T + n * np.eye(n)  # positive definite
    gradients = rng.normal(size=(3, n))
    shifts = linearised_shifts(hessian, gradients)
    assert shifts is not None
    np.testing.assert_allclose(shifts @ hessian, -gradients, atol=1e-9)


def test_a_loose_direction_leaves_the_interval_unmeasured() -> None:
    assert linearised_shifts(np.diag([1.0, -1e-3]), np.ones((2, 2))) is None
    assert linearised_shifts(np.array([[np.nan]]), np.ones((1, 1))) is None


def test_interval_ends_and_coverage() -> None:
    interval = NoiseInterval("k", 200.0, 0.05, 4)
    assert (interval.lower, interval.upper) == pytest.approx((190.0, 210.0))
    assert interval.covers(205.0)
    assert not interval.covers(211.0)
    assert not NoiseInterval("k", 1.0, float("nan"), 0).covers(1.0)


def _signals(q: np.ndarray) -> RecordedSignals:
    n = q.shape[0]
    return RecordedSignals(
        np.arange(n) * 0.01,
        ("j",),
        q - 1.0,  # tracking error 1 rad: the joint term's scale is 1
        q,
        np.full((n, 2), np.nan),  # no ZMP, no tilt: the joint term alone
        np.zeros(n),
    )


def test_the_intervals_match_the_exact_refits_of_a_linear_model(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    r"""q_sim(v) = v x, replicas v̂ x + ε_k: the cost is quadratic, each re-fit exact.

    Exact re-fit of replica k: v_k = xᵀ(v̂ x + ε_k) / xᵀx, so δ_k = xᵀε_k / (v̂ xᵀx); the
    cost mean((v x − q)²) has H = 2 v̂² mean(x²) in relative coordinates.
    """
    rng = np.random.default_rng(3)
    x = rng.uniform(0.5, 1.5, size=(200, 1))
    v_hat, k = 2.0, 6
    monkeypatch.setattr(module, "simulate", lambda problem, values, e: _signals(values[0] * x))
    noise = [0.05 * rng.normal(size=x.shape) for _ in range(k)]
    replicas = [[_signals(v_hat * x + eps)] for eps in noise]
    parameter = FitParameter("gain", "stiffness", 2.0, 0.1, 10.0, "-", effect="M")
    experiment = SimpleNamespace(signals=_signals(v_hat * x))
    problem = FitProblem(get_robot("nao"), "M", (parameter,), {}, (experiment,))  # type: ignore[arg-type]
    hessian = np.array([[2.0 * v_hat**2 * float(np.mean(x**2))]])
    (interval,) = noise_intervals(problem, np.array([v_hat]), hessian, replicas)
    exact = np.array([float(x.ravel() @ eps.ravel()) / (v_hat * float(x.ravel() @ x.ravel()))
                      for eps in noise])  # fmt: skip
    expected = student_t.ppf(0.975, k) * np.sqrt(np.mean(exact**2))
    assert interval.half_width == pytest.approx(expected, rel=1e-9)
    assert interval.replicas == k
