r"""Gauss–Newton refinement of a fit: Levenberg–Marquardt on the cost's residual vector.

CMA-ES finds the basin; on many parameters it spends hundreds of rollouts crawling along
its valleys (the built-in walker's whole catalogue, 12 parameters, stopped at 7 times the
truth's cost after 440). The cost is a sum of squares (:mod:`~zmpkit.simfit.cost_residuals`), so a
trust-region Gauss–Newton step uses the whole residual vector: with its Jacobian
:math:`J = \partial r / \partial u` in the fit's normalised coordinates :math:`u \in [0, 1]^n`
(:mod:`~zmpkit.simfit.parameters`), the step solves

.. math:: \min_{\delta}\ \lVert r + J \delta \rVert^2 \quad \text{within the trust region
          and the bounds}

(:func:`scipy.optimize.least_squares`, ``trf``: a reflective trust region that keeps every
parameter inside its bounds, each scaled by its Jacobian column). :math:`J` is taken by
forward differences of :data:`FD_STEP` in :math:`u` (backward at an upper bound): one
batch of :math:`n` candidates per iteration, evaluated together, as a CMA-ES generation is.
A candidate whose rollout does not reproduce the recording (a fall) has no residual vector;
it counts as :data:`~zmpkit.simfit.cost.FAILED_COST`, so the trust region shrinks away from
it, and in a Jacobian its column is zero (no information there).

``identify sim --refine lm`` starts it from CMA-ES's best and from the catalogue's nominal
values and keeps the cheapest of the two ends and CMA-ES's best. Measured on the built-in
walker's whole catalogue (M, G, F, S, C; three 6 s open-loop walks of a self-test truth,
expected sensor readings): from the nominal values, 21 residual evaluations (189 rollouts)
reach cost 0.0028, where CMA-ES reached 0.0085 in 440 (the truth: 0.0012).
"""

from __future__ import annotations

import json
import multiprocessing
import signal
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from zmpkit.simfit.batched import simulate_batches
from zmpkit.simfit.cost import FAILED_COST
from zmpkit.simfit.cost_residuals import experiment_residuals, stacked_residuals
from zmpkit.simfit.open_loop import is_open_loop
from zmpkit.simfit.parameters import ParameterValues, from_unit, to_unit
from zmpkit.simfit.problem import FitProblem, simulate

__all__ = [
    "FD_STEP",
    "MAX_EVALUATIONS",
    "REFINEMENTS",
    "REFINEMENT_FILE",
    "LeastSquaresRefit",
    "ResidualEvaluator",
    "refine_fit",
    "refinement_doc",
    "refinement_line",
    "write_refinement",
]

REFINEMENT_FILE = "refinement.json"
"""What the refinement did, in a fit's folder (:func:`write_refinement`)."""
REFINEMENTS = ("none", "lm")
"""What follows CMA-ES (``identify sim --refine``): nothing, or Levenberg–Marquardt."""
FD_STEP = 0.03
r"""Forward-difference step of the Jacobian, in normalised coordinates [-] (3 % of a linear
parameter's range; :math:`e^{0.03 \ln(hi/lo)}` of a log-scaled one: 8.8 % of the built-in
walker's gear stiffness). The cost is rough on small scales: a walk's ZMP term is 0.00002
at a self-test's truth (its own simulator replays the contacts exactly) and 0.0006–0.0011
under a 0.5 % change of the gear stiffness (contact timing moves in whole ticks), a static
crouch's rises fourfold (friction and backlash let the joints settle anywhere in their dead
bands). A secant over 3 % sees the bowl under that roughness: on the built-in walker's
whole catalogue (seed 1's three walks, from the nominal values) it ends at cost 0.0028
where a step of 1 % ends at 0.0037."""
MAX_EVALUATIONS = 25
"""Residual evaluations of the refinement (each trial point; Jacobians are extra) [-]."""

ResidualBatch = Callable[[Sequence[NDArray[np.float64]]], list[NDArray[np.float64] | None]]
"""Residual vectors of candidates [units], None for a rollout that fell."""


@dataclass(frozen=True)
class LeastSquaresRefit:
    r"""The refinement's outcome.

    Attributes:
        values: the refined parameters [units].
        cost: their cost [-] (the fit's: the squared residual norm).
        start_cost: the starting point's cost [-].
        evaluations: residual evaluations at trial points [-].
        rollouts: candidates simulated in all, Jacobians included [-].
        jacobian: :math:`\partial r / \partial u` at ``values`` [-], shape (m, n).
        message: why the iterations stopped (SciPy's words).
    """

    values: NDArray[np.float64]
    cost: float
    start_cost: float
    evaluations: int
    rollouts: int
    jacobian: NDArray[np.float64]
    message: str

    @property
    def improved(self) -> bool:
        """Whether it ended cheaper than it started."""
        return self.cost < self.start_cost


def _init_worker(problem: FitProblem) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    global _PROBLEM
    _PROBLEM = problem


_PROBLEM: FitProblem | None = None


def _residual_task(values: list[float], index: int) -> NDArray[np.float64] | None:
    problem = _PROBLEM
    assert problem is not None
    experiment = problem.experiments[index]
    return experiment_residuals(
        experiment.signals,
        simulate(problem, values, index),
        problem.weights,
        problem.models_loads,
    )


class ResidualEvaluator:
    """Residual vectors of candidates on every experiment of ``problem``.

    Open-loop experiments run as MuJoCo thread-pool batches of ``workers`` threads
    (:func:`~zmpkit.simfit.batched.simulate_batches`: the serial path's signals, bit for
    bit); walks re-simulated in closed loop and walk-log windows on a ``spawn`` pool of
    ``workers`` processes (started on first use).
    """

    def __init__(self, problem: FitProblem, workers: int = 2) -> None:
        self.problem = problem
        self.workers = workers
        self.batched = [i for i, e in enumerate(problem.experiments) if is_open_loop(e)]
        self.pooled = [i for i in range(len(problem.experiments)) if i not in self.batched]
        self._pool: ProcessPoolExecutor | None = None

    def _executor(self) -> ProcessPoolExecutor:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(
                self.workers,
                mp_context=multiprocessing.get_context("spawn"),
                initializer=_init_worker,
                initargs=(self.problem,),
            )
        return self._pool

    def __call__(self, candidates: Sequence[NDArray[np.float64]]) -> list[NDArray | None]:
        """The stacked residual vector of each candidate [units] (None: a rollout fell)."""
        problem = self.problem
        parts: list[list[NDArray | None]] = [[None] * len(problem.experiments) for _ in candidates]
        futures = []
        if self.pooled:
            pool = self._executor()
            futures = [
                (c, i, pool.submit(_residual_task, np.asarray(v, float).tolist(), i))
                for c, v in enumerate(candidates)
                for i in self.pooled
            ]
        if self.batched:
            truths = [problem.truth(np.asarray(v, dtype=float).tolist()) for v in candidates]
            chosen = [problem.experiments[i] for i in self.batched]
            simulated = simulate_batches(chosen, truths, problem.sim_effects, self.workers)
            for i, signals in zip(self.batched, simulated, strict=True):
                experiment = problem.experiments[i]
                for c in range(len(candidates)):
                    parts[c][i] = experiment_residuals(
                        experiment.signals, signals[c], problem.weights, problem.models_loads
                    )
        for c, i, future in futures:
            parts[c][i] = future.result()
        return [stacked_residuals(p) for p in parts]

    def close(self) -> None:
        """Shut the process pool down, if one was started."""
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None


def refine_fit(
    problem: FitProblem,
    start: ParameterValues,
    residuals: ResidualBatch,
    max_evaluations: int = MAX_EVALUATIONS,
) -> LeastSquaresRefit:
    """Levenberg–Marquardt from ``start`` [units] on ``problem`` (module docstring).

    Args:
        problem: the fit problem (its parameters and bounds).
        start: the starting values [units], e.g. CMA-ES's best.
        residuals: the residual vectors of a batch of candidates (:class:`ResidualEvaluator`).
        max_evaluations: trial points at most.

    Returns:
        The refined values, or ``start`` itself when its rollout fell.
    """
    params = problem.parameters
    n = len(params)
    u0 = np.clip(to_unit(params, np.asarray(start, dtype=np.float64).tolist()), 0.0, 1.0)
    first = residuals([from_unit(params, u0.tolist())])[0]
    if first is None:
        return LeastSquaresRefit(
            np.asarray(start, float), FAILED_COST, FAILED_COST, 1, 1, np.zeros((0, n)), "fell"
        )
    failed = np.zeros_like(first)
    failed[0] = np.sqrt(FAILED_COST)
    seen: dict[bytes, NDArray[np.float64]] = {u0.tobytes(): first}
    rollouts = [1]

    def fun(u: NDArray[np.float64]) -> NDArray[np.float64]:
        key = np.asarray(u, dtype=np.float64).tobytes()
        if key not in seen:
            r = residuals([from_unit(params, u.tolist())])[0]
            rollouts[0] += 1
            seen[key] = failed if r is None else r
        return seen[key]

    def jac(u: NDArray[np.float64]) -> NDArray[np.float64]:
        r = fun(u)
        h = np.where(u + FD_STEP <= 1.0, FD_STEP, -FD_STEP)
        moved = [np.clip(u + h[k] * axis, 0.0, 1.0) for k, axis in enumerate(np.eye(n))]
        columns = residuals([from_unit(params, m.tolist()) for m in moved])
        rollouts[0] += n
        return np.column_stack(
            [np.zeros_like(r) if c is None else (c - r) / h[k] for k, c in enumerate(columns)]
        )

    result = least_squares(
        fun, u0, jac=jac, bounds=(0.0, 1.0), method="trf", x_scale="jac",
        max_nfev=max_evaluations,
    )  # fmt: skip
    end = fun(result.x)
    return LeastSquaresRefit(
        from_unit(params, result.x.tolist()),
        float(end @ end),
        float(first @ first),
        int(result.nfev),
        rollouts[0],
        np.asarray(result.jac, dtype=np.float64),
        str(result.message),
    )


def refinement_doc(refits: dict[str, LeastSquaresRefit], cma_cost: float) -> dict:
    """What the refinement did, as ``refinement.json`` holds it.

    Keys: ``method`` (``"levenberg-marquardt"``), ``cma_cost``, ``kept`` (the start whose end
    was kept, or None when CMA-ES's best stayed the cheapest), and ``starts``: per start
    name, ``start_cost``, ``cost``, ``evaluations``, ``rollouts``, ``message`` and
    ``values`` [units, in the catalogue's order].
    """
    best = min(refits, key=lambda name: refits[name].cost) if refits else None
    return {
        "method": "levenberg-marquardt",
        "cma_cost": cma_cost,
        "kept": best if best is not None and refits[best].cost < cma_cost else None,
        "starts": {
            name: {
                "start_cost": r.start_cost,
                "cost": r.cost,
                "evaluations": r.evaluations,
                "rollouts": r.rollouts,
                "message": r.message,
                "values": r.values.tolist(),
            }
            for name, r in refits.items()
        },
    }


def write_refinement(doc: dict, path: Path) -> Path:
    """Write :func:`refinement_doc`'s ``doc`` as ``refinement.json`` at ``path``."""
    path.write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
    return path


def refinement_line(doc: dict) -> str:
    """One line: CMA-ES's best cost, each start's end and rollouts, which was kept."""
    ends = ", ".join(
        f"from {name.replace('_', ' ')} {start['cost']:.4g} ({start['rollouts']} rollouts)"
        for name, start in doc["starts"].items()
    )
    kept = doc["kept"].replace("_", " ") if doc["kept"] else "none: CMA-ES's best kept"
    return f"refinement (Levenberg-Marquardt): CMA-ES {doc['cma_cost']:.4g}; {ends}; kept {kept}"
