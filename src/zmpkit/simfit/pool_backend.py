"""Rollouts on a local process pool, and the ``local`` backend's split of a generation.

- :class:`LocalPoolEvaluator`: a ``spawn`` process pool of ``workers`` processes, one
  rollout per task on the serial path; each worker gets the problem once and ignores Ctrl-C
  (the parent handles it and shuts the pool down).
- :class:`RoutedEvaluator`: the ``local`` backend when some experiments are walks
  re-simulated in closed loop (:mod:`~zmpkit.simfit.closed_loop`): the open-loop
  experiments run as MuJoCo thread-pool batches
  (:class:`~zmpkit.simfit.batch_backend.BatchEvaluator`), the closed-loop ones on the pool;
  the costs are those of the serial path.
"""

from __future__ import annotations

import multiprocessing
import signal
from collections.abc import Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import replace

import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.simfit.batch_backend import BatchEvaluator
from zmpkit.simfit.cost import CostTerms
from zmpkit.simfit.open_loop import is_open_loop
from zmpkit.simfit.parameters import ParameterValues
from zmpkit.simfit.problem import FitProblem, evaluate

__all__ = ["DEFAULT_WORKERS", "Costs", "LocalPoolEvaluator", "RoutedEvaluator", "pairs", "regroup"]

DEFAULT_WORKERS = 2
"""Threads of the local batch, or processes of the pool."""

Costs = list[list[CostTerms]]
"""``costs[c][e]``: the cost terms of candidate c on experiment e."""


def pairs(problem: FitProblem, candidates: Sequence[ParameterValues]) -> list[tuple[int, int]]:
    """Every (candidate, experiment) index pair, candidate-major."""
    return [(c, e) for c in range(len(candidates)) for e in range(len(problem.experiments))]


def regroup(flat: Sequence[CostTerms], n_candidates: int) -> Costs:
    """Candidate-major flat cost terms as ``[c][e]``."""
    per = len(flat) // max(n_candidates, 1)
    return [list(flat[c * per : (c + 1) * per]) for c in range(n_candidates)]


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
        self.width = max(1, workers // max(1, len(problem.experiments)))  # a task per experiment
        context = multiprocessing.get_context("spawn")
        self._pool = ProcessPoolExecutor(
            workers, mp_context=context, initializer=_init_worker, initargs=(problem,)
        )

    def submit(self, candidates: Sequence[ParameterValues]) -> list[Future[CostTerms]]:
        """Start every (candidate, experiment) rollout; :meth:`costs` collects them."""
        return [
            self._pool.submit(_worker_task, np.asarray(candidates[c], float).tolist(), e)
            for c, e in pairs(self.problem, candidates)
        ]

    def costs(self, candidates: Sequence[ParameterValues]) -> Costs:
        """Cost terms per candidate and experiment."""
        return regroup([f.result() for f in self.submit(candidates)], len(candidates))

    def close(self) -> None:
        """Stop the workers (pending tasks are cancelled)."""
        self._pool.shutdown(wait=True, cancel_futures=True)


class RoutedEvaluator:
    """Open-loop experiments in thread-pool batches, closed-loop walks on a process pool.

    Args:
        problem: the fit problem (at least one of its experiments closed loop).
        workers: threads of the batches, and processes of the pool.
    """

    def __init__(self, problem: FitProblem, workers: int = DEFAULT_WORKERS) -> None:
        experiments = problem.experiments
        self.problem = problem
        self._open = [e for e, x in enumerate(experiments) if is_open_loop(x)]
        self._closed = [e for e, x in enumerate(experiments) if not is_open_loop(x)]
        self._pool = LocalPoolEvaluator(self._part(self._closed), workers)
        self._batch = BatchEvaluator(self._part(self._open), workers) if self._open else None
        self.width = self._pool.width

    def _part(self, indices: list[int]) -> FitProblem:
        return replace(
            self.problem, experiments=tuple(self.problem.experiments[i] for i in indices)
        )

    def costs(self, candidates: Sequence[ParameterValues]) -> Costs:
        """Cost terms per candidate and experiment, in the problem's experiment order.

        The pool's rollouts start first and run while the batches do.
        """
        futures = self._pool.submit(candidates)
        batch = self._batch.costs(candidates) if self._batch is not None else []
        closed = regroup([f.result() for f in futures], len(candidates))
        out = []
        for c in range(len(candidates)):
            row: dict[int, CostTerms] = dict(zip(self._closed, closed[c], strict=True))
            if batch:
                row.update(zip(self._open, batch[c], strict=True))
            out.append([row[e] for e in range(len(self.problem.experiments))])
        return out

    def close(self) -> None:
        """Stop the pool."""
        self._pool.close()
