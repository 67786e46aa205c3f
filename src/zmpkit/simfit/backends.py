"""Where rollouts run: in this process, on a local process pool, or on a Ray cluster.

Every backend takes a list of candidate parameter vectors and returns, per candidate, the
:class:`~zmpkit.simfit.cost.CostTerms` of every experiment; the work is split into
one task per (candidate, experiment) pair.

- ``"local"`` (default): this machine, ``workers`` cores. The open-loop experiments of a
  generation run as MuJoCo thread-pool batches in this process
  (:class:`~zmpkit.simfit.batch_backend.BatchEvaluator`): all candidates of an
  experiment in one batch, no Python per physics step. Walks re-simulated with their
  feedback controller (:mod:`~zmpkit.simfit.closed_loop`: Python at every motion frame)
  run on a process pool of ``workers`` processes beside them
  (:class:`~zmpkit.simfit.pool_backend.RoutedEvaluator`).
- ``"pool"``: a ``spawn`` process pool of ``workers`` processes, one rollout per task on the
  serial path; each worker gets the problem once, ignores Ctrl-C (the parent handles it and
  shuts the pool down).
- ``"serial"``: this process, one rollout at a time (benchmarks, debugging).
- ``"warp"``: the local batches on MuJoCo Warp, on its default device (a GPU where there is
  one; ``pip install 'zmpkit[gpu]'``): float32 physics, models with the M effect on;
  open-loop experiments only — it refuses a walk re-simulated in closed loop (the GPU would
  wait on Python controllers: use ``local``).
- ``"ray"``: tasks on a Ray cluster (``pip install zmpkit[ray]``). Start the head node on
  one machine and let the others join it::

      ray start --head --port=6379              # on the head; prints its address
      ray start --address=HEAD_IP:6379          # on every worker machine
      zmpkit identify sim DATA --backend ray --address HEAD_IP:6379 ...
      ray stop                                  # on every machine, when done

  Every machine needs the same Python, Ray and zmpkit versions installed (workers import
  zmpkit; ``ray start`` must run from that environment). Ray >= 2.59 may start the head with
  token authentication (Ray 2.60's ``ray start --head`` did here once ``~/.ray/auth_token``
  existed, which a local ``ray.init()`` creates); then every worker and the ``zmpkit``
  driver need ``RAY_AUTH_MODE=token`` and the head's token (``ray get-auth-token``, as
  ``RAY_AUTH_TOKEN`` or in ``~/.ray/auth_token``) in their environment, except a driver on
  the head given ``--address auto``. ``address="auto"`` joins a cluster
  started on this machine (an error if there is none); ``address=None`` joins such a cluster
  too when one is running, and otherwise starts a private Ray instance for this process,
  stopped again by :meth:`RayEvaluator.close`. An explicit ``HOST:PORT`` that nothing listens
  on is an error within seconds (Ray itself would retry for minutes). The problem
  (experiments and base truth) is put once in the object store; costs are identical to the
  serial backend's for the same candidates.
"""

from __future__ import annotations

import logging
import socket
from collections.abc import Sequence
from types import ModuleType
from typing import Protocol

import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.simfit.batch_backend import BatchEvaluator
from zmpkit.simfit.open_loop import is_open_loop
from zmpkit.simfit.parameters import ParameterValues
from zmpkit.simfit.pool_backend import (
    DEFAULT_WORKERS,
    Costs,
    LocalPoolEvaluator,
    RoutedEvaluator,
    pairs,
    regroup,
)
from zmpkit.simfit.problem import FitProblem, evaluate

__all__ = [
    "BACKENDS",
    "DEFAULT_WORKERS",
    "RAY_CONNECT_TIMEOUT_S",
    "Evaluator",
    "LocalPoolEvaluator",
    "RayEvaluator",
    "SerialEvaluator",
    "make_evaluator",
]

BACKENDS: tuple[str, ...] = ("local", "pool", "serial", "ray", "warp")
"""Valid backend names."""


class Evaluator(Protocol):
    """Evaluates candidates: ``costs(values)[c][e]`` for candidate c, experiment e.

    ``width``: how many candidates it evaluates in about the wall time of one (its cores,
    or a GPU's batch), which sizes the fit's population (:mod:`~zmpkit.simfit.population`).
    """

    @property
    def width(self) -> int:
        """Candidates evaluated in about the wall time of one."""
        ...

    def costs(self, candidates: Sequence[ParameterValues]) -> Costs:
        """Return the cost terms ``[c][e]`` of every candidate c on every experiment e."""
        ...

    def close(self) -> None:
        """Release the evaluator's workers (threads, processes or a Ray connection)."""
        ...


class SerialEvaluator:
    """Runs every rollout in this process."""

    def __init__(self, problem: FitProblem) -> None:
        self.problem = problem
        self.width = 1

    def costs(self, candidates: Sequence[ParameterValues]) -> Costs:
        """Cost terms per candidate and experiment."""
        flat = [
            evaluate(self.problem, candidates[c], e) for c, e in pairs(self.problem, candidates)
        ]
        return regroup(flat, len(candidates))

    def close(self) -> None:
        """Nothing to release."""


def _ray_module() -> ModuleType:
    """Ray, or an error saying how to install it."""
    try:
        import ray
    except ImportError:
        raise ParameterError(
            "backend 'ray' needs Ray, which is not installed: pip install zmpkit[ray] "
            f"(or use a backend from: {', '.join(b for b in BACKENDS if b != 'ray')})"
        ) from None
    return ray


RAY_CONNECT_TIMEOUT_S = 5.0
"""How long [s] an explicit ``HOST:PORT`` address may take to accept a TCP connection."""


def _check_ray_address(address: str) -> None:
    """Fail fast when nothing listens at an explicit ``[ray://]HOST:PORT`` address.

    Raises:
        ParameterError: the address is ``HOST:PORT`` but the connection is refused or times out.
    """
    target = address.removeprefix("ray://")
    host, sep, port = target.rpartition(":")
    if not sep or not host or not port.isdigit():
        return  # "auto", "local" and other forms are left to Ray
    try:
        with socket.create_connection((host.strip("[]"), int(port)), RAY_CONNECT_TIMEOUT_S):
            pass
    except OSError as exc:
        raise ParameterError(
            f"no Ray cluster at --address {address} ({exc}); start its head there with "
            f"'ray start --head --port={port}', or omit --address for a local Ray instance"
        ) from None


class RayEvaluator:
    """Tasks on a Ray cluster (module docstring for starting one).

    Args:
        problem: the fit problem, put once in the object store.
        address: ``HOST:PORT`` of a running head, ``"auto"`` or None (see the module).

    Raises:
        ParameterError: Ray not installed, or no cluster at ``address``.
    """

    def __init__(self, problem: FitProblem, address: str | None = None) -> None:
        ray = _ray_module()
        self.problem = problem
        self._ray = ray
        self._owns_ray = False
        if not ray.is_initialized():
            if address is not None:
                _check_ray_address(address)
            try:
                ray.init(address=address, logging_level=logging.WARNING)
            except (ConnectionError, ValueError, RuntimeError) as exc:
                hint = ""
                if isinstance(exc, ConnectionError) and address not in (None, "auto"):
                    hint = (
                        "; if the cluster uses token authentication (Ray >= 2.59 turns it on "
                        "for clusters started on this machine), export RAY_AUTH_MODE=token "
                        "and its token (ray get-auth-token) as RAY_AUTH_TOKEN, or use "
                        "--address auto on the head"
                    )
                raise ParameterError(
                    f"cannot join Ray at address {address!r}: {exc}{hint}"
                ) from None
            self._owns_ray = True
        self._problem_ref = ray.put(problem)
        self._task = ray.remote(evaluate)
        cpus = int(ray.cluster_resources().get("CPU", 1))
        self.width = max(1, cpus // max(1, len(problem.experiments)))  # a task per experiment

    def costs(self, candidates: Sequence[ParameterValues]) -> Costs:
        """Cost terms per candidate and experiment; on Ctrl-C the pending tasks are cancelled."""
        if self._problem_ref is None:
            raise ParameterError("this RayEvaluator is closed; make a new one")
        refs = [
            self._task.remote(self._problem_ref, np.asarray(candidates[c], float).tolist(), e)
            for c, e in pairs(self.problem, candidates)
        ]
        try:
            return regroup(self._ray.get(refs), len(candidates))
        except KeyboardInterrupt:
            for ref in refs:
                self._ray.cancel(ref)
            raise

    def close(self) -> None:
        """Drop the problem reference; disconnect from Ray if this evaluator connected.

        A cluster started with ``ray start`` keeps running (it is the user's); a private
        instance started by ``address=None`` stops. Ray initialised by the caller before this
        evaluator was made is left as it is. Calling close twice is harmless.
        """
        self._problem_ref = None
        if self._owns_ray and self._ray.is_initialized():
            self._ray.shutdown()
        self._owns_ray = False


def _refuse_closed_loop(problem: FitProblem) -> None:
    closed = [e.name for e in problem.experiments if not is_open_loop(e)]
    if closed:
        raise ParameterError(
            f"backend 'warp' replays open-loop experiments only; {closed[0]} runs on the CPU "
            "(a walk with a feedback controller, re-simulated in closed loop, or a walk-log "
            "window started from its measured state): use --backend local"
        )


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
        if all(is_open_loop(e) for e in problem.experiments):
            return BatchEvaluator(problem, workers)
        return RoutedEvaluator(problem, workers)
    if backend == "pool":
        return LocalPoolEvaluator(problem, workers)
    if backend == "warp":
        try:
            import mujoco_warp  # noqa: F401
        except ImportError:
            raise ParameterError(
                "backend 'warp' needs MuJoCo Warp, which is not installed: "
                "pip install 'zmpkit[gpu]' (or use backend 'local', MuJoCo's CPU threads)"
            ) from None
        _refuse_closed_loop(problem)
        return BatchEvaluator(problem, workers, warp_device="")
    if backend == "ray":
        return RayEvaluator(problem, address)
    raise ParameterError(f"backend must be one of {', '.join(BACKENDS)}; got {backend!r}")
