"""A generation's candidates as one compiled model and per-candidate fields: no MJCF each.

A fit's candidates differ only in the numbers of their truth files that the fit changes.
:func:`candidate_worlds` compiles the robot once (the first candidate's MJCF) and writes
every candidate's numbers into the fields of that model, one row per candidate, with the
robot's :class:`~zmpkit.robots.field_rule.FieldRule`; the sensor effects (S), which act on
the host, become each candidate's robot description with its own F-T offsets (sharing the
rest). The fields are those of each candidate's own compiled MJCF, to float64 equality
(``tests/simfit/test_candidate_worlds.py``), so the rollouts are the same.

:func:`field_map_gap` says why a set of parameters cannot go this way (a robot without a
rule, a parameter its rule does not map): the fit then builds each candidate's truth and
compiles its MJCF (:func:`~zmpkit.simfit.open_loop.posed_simulations`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.robots.robot import Robot
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.world_fields import WorldFields
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.truth_doc import RobotTruth, doc_with_columns, load_robot_truth, truth_doc_with

__all__ = ["CandidateValues", "CandidateWorlds", "candidate_worlds", "field_map_gap"]


@dataclass(frozen=True, eq=False)
class CandidateValues:
    """A generation's candidates as parameter values, and what makes each one's truth.

    Attributes:
        robot: the robot fitted.
        parameters: the fitted parameters.
        base_doc: the truth document that holds every number not fitted.
        values: ``(ncandidate, len(parameters))`` each candidate's values [units].
    """

    robot: Robot
    parameters: tuple[FitParameter, ...]
    base_doc: Mapping[str, Any]
    values: NDArray[np.float64]

    def __len__(self) -> int:
        return int(self.values.shape[0])

    def truth(self, candidate: int) -> RobotTruth:
        """Candidate ``candidate``'s truth object (as the serial path builds it)."""
        doc = truth_doc_with(self.base_doc, self.parameters, self.values[candidate].tolist())
        return load_robot_truth(self.robot, doc)

    def truths(self) -> list[RobotTruth]:
        """Every candidate's truth object."""
        return [self.truth(c) for c in range(len(self))]


@dataclass(frozen=True, eq=False)
class CandidateWorlds:
    """The candidates as one compiled model with per-candidate fields and descriptions.

    Attributes:
        description: the first candidate's robot description (the template's MJCF).
        fields: the template and each candidate's fields (one world per candidate).
        ft_offsets: foot -> ``(ncandidate, 6)`` each candidate's F-T offset [N, N·m].
    """

    description: RobotDescription
    fields: WorldFields
    ft_offsets: Mapping[str, NDArray[np.float64]]

    def description_of(self, candidate: int) -> RobotDescription:
        """Candidate ``candidate``'s description: the template's, with its F-T offsets."""
        if not self.ft_offsets:
            return self.description
        offsets = dict(self.description.ft_offsets)
        for foot, rows in self.ft_offsets.items():
            offsets[foot] = tuple(rows[candidate].tolist())
        return dataclasses.replace(self.description, ft_offsets=offsets)


def field_map_gap(robot: Robot, parameters: Sequence[FitParameter]) -> str | None:
    """Why the candidates of ``parameters`` need a compilation each, or None if they do not."""
    rule = robot.fit.fields if robot.fit is not None else None
    if rule is None:
        return f"{robot.title} has no map from its fit parameters to model fields"
    unmapped = [p.name for p in parameters if not rule.maps(p.path)]
    if unmapped:
        return f"{robot.title}'s field map does not cover the parameters {unmapped}"
    return None


def candidate_worlds(candidates: CandidateValues, effects: str) -> CandidateWorlds:
    """The candidates as one compiled model (the first's) with each one's fields written.

    Raises:
        ParameterError: on parameters the robot's rule does not map (:func:`field_map_gap`),
            or a truth document it cannot map.
    """
    robot = candidates.robot
    rule = robot.fit.fields if robot.fit is not None else None
    gap = field_map_gap(robot, candidates.parameters)
    if gap is not None or rule is None:
        raise ParameterError(gap or "no field rule")
    description = robot.description(effects, candidates.truth(0))
    template = mujoco.MjModel.from_xml_string(description.mjcf)
    doc = doc_with_columns(candidates.base_doc, candidates.parameters, candidates.values)
    n = len(candidates)
    written = rule.write(template, description, doc, n)
    fields = WorldFields.of_writes(template, written.writes, n, written.derived)
    return CandidateWorlds(description, fields, written.ft_offsets)
