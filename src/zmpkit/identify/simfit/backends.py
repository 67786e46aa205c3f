"""Where rollouts run: in this process, on a local process pool, or on a Ray cluster.

Every backend takes a list of candidate parameter vectors and returns, per candidate, the
:class:`~zmpkit.identify.simfit.cost.CostTerms` of every experiment; the work is split into
one task per (candidate, experiment) pair.

- ``"serial"``: this process (benchmarks, debugging).
- ``"local"`` (default): a ``spawn`` process pool of ``workers`` processes; each worker gets
  the problem once, ignores Ctrl-C (the parent handles it and shuts the pool down).
- ``"ray"``: tasks on a Ray cluster (``pip install zmpkit[ray]``). Start the head node on
  one machine and let the others join it::

      ray start --head --port=6379              # on the head; prints its address
      ray start --address=HEAD_IP:6379          # on every worker machine
      zmpkit identify sim DATA --backend ray --address HEAD_IP:6379 ...

  Every machine needs the same Python and zmpkit version installed. ``address="auto"``
  joins a cluster started on this machine; ``address=None`` starts a local Ray instance.
  The problem (experiments and base truth) is put once in the object store.
"""

from __future__ import annotations

import multiprocessing
import signal
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Protocol

import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.identify.simfit.cost import CostTerms
from zmpkit.identify.simfit.problem import FitProblem, evaluate

__all__ = [
    "BACKENDS",
    "DEFAULT_WORKERS",
    "Evaluator",
    "LocalPoolEvaluator",
    "RayEvaluator",
    "SerialEvaluator",
    "make_evaluator",
]

BACKENDS: tuple[str, ...] = ("local", "serial", "ray")
"""Valid backend names."""
DEFAULT_WORKERS = 2
"""Processes of the local pool."""

Costs = list[list[CostTerms]]


class Evaluator(Protocol):
    """Evaluates candidates: ``costs(values)[c][e]`` for candidate c, experiment e."""

    def costs(self, candidates: Sequence[Sequence[float]]) -> Costs: ...

    def close(self) -> None: ...


def _pairs(problem: FitProblem, candidates: Sequence[Sequence[float]]) -> list[tuple[int, int]]:
    return [(c, e) for c in range(len(candidates)) for e in range(len(problem.experiments))]


def _regroup(flat: Sequence[CostTerms], n_candidates: int) -> Costs:
    per = len(flat) // max(n_candidates, 1)
    return [list(flat[c * per : (c + 1) * per]) for c in range(n_candidates)]


class SerialEvaluator:
    """Runs every rollout in this process."""

    def __init__(self, problem: FitProblem) -> None:
        self.problem = problem

    def costs(self, candidates: Sequence[Sequence[float]]) -> Costs:
        """Cost terms per candidate and experiment."""
        flat = [
            evaluate(self.problem, candidates[c], e) for c, e in _pairs(self.problem, candidates)
        ]
        return _regroup(flat, len(candidates))

    def close(self) -> None:
        """Nothing to release."""


_WORKER_PROBLEM: FitProblem | None = None


def _init_worker(problem: FitProblem) -> None:
    global _WORKER_PROBLEM
    _WORKER_PROBLEM = problem
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _worker_task(values: list[float], index: int) -> CostTerms:
    assert _WORKER_PROBLEM is not None
    return evaluate(_WORKER_PROBLEM, values, index)


class LocalPoolEvaluator:
    """A ``spawn`` process pool; each worker holds the problem."""

    def __init__(self, problem: FitProblem, workers: int = DEFAULT_WORKERS) -> None:
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
        self.problem = problem
        context = multiprocessing.get_context("spawn")
        self._pool = ProcessPoolExecutor(
            workers, mp_context=context, initializer=_init_worker, initargs=(problem,)
        )

    def costs(self, candidates: Sequence[Sequence[float]]) -> Costs:
        """Cost terms per candidate and experiment."""
        pairs = _pairs(self.problem, candidates)
        futures = [
            self._pool.submit(_worker_task, np.asarray(candidates[c], float).tolist(), e)
            for c, e in pairs
        ]
        return _regroup([f.result() for f in futures], len(candidates))

    def close(self) -> None:
        """Stop the workers (pending tasks are cancelled)."""
        self._pool.shutdown(wait=True, cancel_futures=True)


def _ray_module():
    try:
        import ray
    except ImportError:
        raise ParameterError(
            "backend 'ray' needs Ray, which is not installed: pip install zmpkit[ray] "
            f"(or use a backend from: {', '.join(b for b in BACKENDS if b != 'ray')})"
        ) from None
    return ray


class RayEvaluator:
    """Tasks on a Ray cluster (module docstring for starting one)."""

    def __init__(self, problem: FitProblem, address: str | None = None) -> None:
        ray = _ray_module()
        self.problem = problem
        self._ray = ray
        if not ray.is_initialized():
            ray.init(address=address)
        self._problem_ref = ray.put(problem)
        self._task = ray.remote(evaluate)

    def costs(self, candidates: Sequence[Sequence[float]]) -> Costs:
        """Cost terms per candidate and experiment."""
        refs = [
            self._task.remote(self._problem_ref, np.asarray(candidates[c], float).tolist(), e)
            for c, e in _pairs(self.problem, candidates)
        ]
        return _regroup(self._ray.get(refs), len(candidates))

    def close(self) -> None:
        """Leave the cluster running (it is the user's); drop the problem reference."""
        self._problem_ref = None


def make_evaluator(
    problem: FitProblem, backend: str, workers: int = DEFAULT_WORKERS, address: str | None = None
) -> Evaluator:
    """The evaluator of ``backend`` (one of :data:`BACKENDS`).

    Raises:
        ParameterError: on an unknown backend, or ``"ray"`` without Ray installed.
    """
    if backend == "serial":
        return SerialEvaluator(problem)
    if backend == "local":
        return LocalPoolEvaluator(problem, workers)
    if backend == "ray":
        return RayEvaluator(problem, address)
    raise ParameterError(f"backend must be one of {', '.join(BACKENDS)}; got {backend!r}")
