"""The default backend on one machine: a generation's rollouts as MuJoCo thread-pool batches.

Every experiment the fit takes is open loop (:mod:`~zmpkit.simfit.batched`), so a
generation runs as one :class:`mujoco.batch.Batch` per experiment, all candidates at once on
``threads`` threads of this process: no worker processes to start or feed, no Python per
physics step. The costs are those of the serial backend, bit for bit (tested).

With ``warp_device`` the batch runs on MuJoCo Warp instead (``pip install 'zmpkit[gpu]'``;
backend ``"warp"``): all experiments x candidates of a generation stepped together in one
batch on a GPU (:func:`~zmpkit.simfit.warp_batched.costs_batches_warp`), many steps per graph
launch, only the rows and columns the cost reads recorded on the device and the joint term
summed there, the Warp model kept between generations (:mod:`zmpkit.sim.warp_batch`), the
candidates' parameters written into one compiled model's per-world fields where the robot's
field rule maps them (:mod:`~zmpkit.simfit.candidate_worlds`; else one compilation each);
float32 physics, so the costs approximate the
serial backend's (on the test walk within 0.1 % for candidates that walk, and the same fall
frame for one that falls).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.simfit.batched import simulate_batches
from zmpkit.simfit.candidate_worlds import CandidateValues
from zmpkit.simfit.cost import CostTerms, experiment_cost
from zmpkit.simfit.parameters import ParameterValues
from zmpkit.simfit.population import WARP_GPU_WIDTH
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.warp_batched import costs_batches_warp

__all__ = ["BatchEvaluator"]


class BatchEvaluator:
    """Evaluates candidates in MuJoCo thread-pool batches, one per experiment.

    Args:
        problem: the fit problem.
        threads: threads of each batch (the cores to use).
        warp_device: run the batches on MuJoCo Warp on this device (``"cuda:0"``, ``"cpu"``
            for testing; ``""`` for Warp's default device) instead of MuJoCo's thread pool.
    """

    def __init__(
        self, problem: FitProblem, threads: int = 2, warp_device: str | None = None
    ) -> None:
        if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
            raise ParameterError(f"workers must be an integer >= 1, got {threads!r}")
        self.problem = problem
        self.threads = threads
        self.warp_device = warp_device

    @property
    def width(self) -> int:
        """Candidates evaluated in about the wall time of one.

        The threads; on MuJoCo Warp :data:`~zmpkit.simfit.population.WARP_GPU_WIDTH` on a
        CUDA device, 1 on Warp's CPU device.
        """
        if self.warp_device is None:
            return self.threads
        from zmpkit.sim.warp_runtime import warp_runtime

        _, device = warp_runtime(self.warp_device or None)
        return WARP_GPU_WIDTH if device.startswith("cuda") else 1

    def costs(self, candidates: Sequence[ParameterValues]) -> list[list[CostTerms]]:
        """Cost terms per candidate and experiment."""
        problem = self.problem
        if self.warp_device is not None:  # every experiment x candidate in one batch
            values = CandidateValues(
                problem.robot,
                problem.parameters,
                problem.simulated_base_doc,
                np.asarray(candidates, dtype=np.float64).reshape(
                    len(candidates), len(problem.parameters)
                ),
            )  # one compiled model, each candidate's fields written per world
            per_experiment = costs_batches_warp(
                problem.experiments,
                values,
                problem.sim_effects,
                self.warp_device,
                problem.models_loads,
            )
            return [[terms[c] for terms in per_experiment] for c in range(len(candidates))]
        truths = [problem.truth(np.asarray(c, dtype=float).tolist()) for c in candidates]
        simulated = simulate_batches(problem.experiments, truths, problem.sim_effects, self.threads)
        return [
            [
                experiment_cost(experiment.signals, signals[c], problem.models_loads)
                for experiment, signals in zip(problem.experiments, simulated, strict=True)
            ]
            for c in range(len(candidates))
        ]

    def close(self) -> None:
        """Nothing to release."""
