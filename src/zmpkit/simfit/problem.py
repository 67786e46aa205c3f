"""The fit problem as data, and the cost of one candidate on one experiment.

A :class:`FitProblem` is everything a worker needs — robot, switched-on effects, fitted
parameters, the base truth document and the recorded experiments — and is pickled once per
worker (process pool) or put once in the object store (Ray).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.robots.robot import Robot
from zmpkit.simfit.cost import CostTerms, CostWeights, experiment_cost
from zmpkit.simfit.experiments import Experiment
from zmpkit.simfit.parameters import FitParameter, ParameterValues
from zmpkit.simfit.pooled_cost import check_window_pooling, pooled_cost
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import (
    RobotTruth,
    expected_readings,
    load_robot_truth,
    truth_doc_with,
)

__all__ = ["SENSOR_READINGS", "FitProblem", "check_sensor_readings", "evaluate", "simulate"]

SENSOR_READINGS = ("sampled", "expected")
"""How the fit's simulated sensors read (:attr:`FitProblem.sensor_readings`)."""


def check_sensor_readings(value: str) -> None:
    """Raise :class:`~zmpkit.errors.ParameterError`, naming the valid ones, on a bad value."""
    if value not in SENSOR_READINGS:
        raise ParameterError(
            f"sensor readings must be one of {', '.join(SENSOR_READINGS)}; got {value!r}"
        )


@dataclass(frozen=True, eq=False)
class FitProblem:
    """What the fit minimises.

    Attributes:
        robot: the robot fitted (it crosses into a worker as its
            :attr:`~zmpkit.robots.robot.Robot.source`).
        sim_effects: effect letters the simulator runs with, e.g. ``"M,G"``.
        parameters: the fitted parameters.
        base_doc: the base truth document (every unfitted value).
        experiments: the recorded experiments, fitted jointly.
        weights: weights of the cost terms.
        sensor_readings: ``"sampled"``: the simulated sensors run the base truth's whole
            chain (noise with a fixed seed, quantisation); ``"expected"``: their expected
            readings, without noise and quantisation
            (:func:`~zmpkit.simfit.truth_doc.expected_readings`).
        window_pooling: how the logs' windows enter the cost, ``"mean"`` or ``"median"``
            (:mod:`~zmpkit.simfit.pooled_cost`).
    """

    robot: Robot
    sim_effects: str
    parameters: tuple[FitParameter, ...]
    base_doc: dict
    experiments: tuple[Experiment, ...]
    weights: CostWeights = field(default_factory=CostWeights)
    sensor_readings: str = "sampled"
    window_pooling: str = "mean"

    def __post_init__(self) -> None:
        check_sensor_readings(self.sensor_readings)
        check_window_pooling(self.window_pooling)

    @cached_property
    def simulated_base_doc(self) -> dict:
        """The base document the simulator runs from, made once.

        ``base_doc`` with its sensors as :attr:`sensor_readings` asks; ``base_doc`` itself
        stays the user's (the fitted truth is written from it).
        """
        if self.sensor_readings == "expected":
            return expected_readings(self.base_doc)
        return self.base_doc

    @property
    def models_loads(self) -> bool:
        """Whether the fit models the loads, so the cost charges the ZMP's mean and the forces.

        The mean ZMP difference and the feet's vertical forces (:mod:`~zmpkit.simfit.cost`).
        True when F-T offsets (S) or the mass and CoM (C) are fitted, so the simulator
        models what shifts the whole ZMP and what the forces read at rest.
        """
        return any(p.effect in ("S", "C") for p in self.parameters)

    def cost_of(self, terms: Sequence[CostTerms]) -> float:
        """The fit's cost [-] of one candidate from its experiments' terms, in their order.

        Their weighted totals pooled as :attr:`window_pooling` says
        (:func:`~zmpkit.simfit.pooled_cost.pooled_cost`).
        """
        return pooled_cost(
            self.experiments, [t.total(self.weights) for t in terms], self.window_pooling
        )

    def truth(self, values: ParameterValues) -> RobotTruth:
        """The robot's truth object with the parameters at ``values`` [units]."""
        doc = truth_doc_with(self.simulated_base_doc, self.parameters, values)
        return load_robot_truth(self.robot, doc)


def simulate(problem: FitProblem, values: ParameterValues, index: int) -> RecordedSignals:
    """Simulated signals of experiment ``index`` with the parameters at ``values``.

    With the sensor effect on, the noise seed is fixed (0): every candidate sees the same
    noise, so the cost is a deterministic function of the parameters.
    """
    truth = problem.truth(np.asarray(values, dtype=float).tolist())
    return simulate_experiment(problem.experiments[index], truth, problem.sim_effects)


def evaluate(problem: FitProblem, values: ParameterValues, index: int) -> CostTerms:
    """Cost terms of experiment ``index`` with the parameters at ``values`` [units]."""
    simulated = simulate(problem, values, index)
    return experiment_cost(problem.experiments[index].signals, simulated, problem.models_loads)
