"""How a robot's fit parameters land in its compiled model: a truth document's numbers to fields.

A fit evaluates many candidates that differ only in a few numbers of the robot's truth file
(:class:`~zmpkit.robots.fit_parameter.FitParameter`). A :class:`FieldRule` writes those
numbers into the fields of one compiled model of the robot, one row per candidate, without
an MJCF or a compilation per candidate: it reads the truth document as the robot's truth
loader reads it, with a column of values (one per candidate) where the fit changes a number,
and writes what the robot's MJCF builder makes of them
(:mod:`zmpkit.sim.effect_fields`). Each robot gives its own (its fit's
:attr:`~zmpkit.robots.robot.FitSpec.fields`), since only it knows its truth layout.

A parameter whose path no pattern of :attr:`FieldRule.paths` matches has no such map: the
fit then builds and compiles each candidate's MJCF.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.effect_fields import flex_writes, gear_writes
from zmpkit.sim.world_fields import CandidateFields, FieldWrite

__all__ = ["FieldRule", "column", "item"]

FieldWriter = Callable[[mujoco.MjModel, RobotDescription, Mapping[str, Any], int], CandidateFields]
"""``writer(template, description, doc, ncandidate)``: the fields of ``ncandidate``
candidates, for the ``template`` compiled from ``description`` (its effects, joints)."""


@dataclass(frozen=True, eq=False)
class FieldRule:
    """A robot's map from its truth document's numbers to its compiled model's fields.

    Attributes:
        paths: ``fnmatch`` patterns of the truth paths the rule maps (``"gear.stiffness"``,
            ``"flex[*].stiffness[0]"``); a fit parameter elsewhere needs a compilation.
        write: ``write(template, description, doc, n)``: the fields of ``n`` candidates,
            for a template compiled from ``description`` (the effects it simulates, its
            driven joints), from a truth document whose fitted numbers are ``(n,)`` arrays
            (the others plain numbers). Raises a ParameterError when the document holds
            something it cannot map (the fit then compiles each candidate).
    """

    paths: tuple[str, ...]
    write: FieldWriter

    def maps(self, path: str) -> bool:
        """Whether the rule maps the truth path ``path``."""
        return any(fnmatch.fnmatchcase(path, pattern) for pattern in self.paths)


def column(value: Any, n: int) -> NDArray[np.float64]:
    """A truth number (a plain number, or a fitted ``(n,)`` column) as an ``(n,)`` column."""
    return np.broadcast_to(np.asarray(value, dtype=np.float64), (n,))


def item(value: Any) -> Any:
    """A truth number as the loader reads it: ``float`` of a plain number, a column as is."""
    return value if isinstance(value, np.ndarray) else float(value)


def gear_doc_writes(
    model: mujoco.MjModel, joints: Sequence[str], gear: Mapping[str, Any], n: int
) -> list[FieldWrite]:
    """The gear tendons' writes (G) from a truth document's ``gear`` block, ``n`` candidates."""
    return gear_writes(
        model,
        joints,
        column(gear["stiffness"], n),
        column(gear["damping"], n),
        column(gear["backlash"], n),
    )


def ft_offset_columns(
    offsets: Mapping[str, Sequence[Any]], sides: Sequence[str], n: int
) -> dict[str, NDArray[np.float64]]:
    """Per side, the F-T offsets of ``n`` candidates [N, N·m], shape (n, 6)."""
    return {side: np.stack([column(v, n) for v in offsets[side]], 1) for side in sides}


def flex_doc_writes(
    model: mujoco.MjModel, entries: Sequence[Mapping[str, Any]], n: int
) -> list[FieldWrite]:
    """The link-flex joints' writes (F) from a truth document's ``flex`` entries.

    Raises:
        ParameterError: on a softening spring (its tendon stages have no field map here).
    """
    if not entries:
        return []
    if any(float(e.get("softening_torque", 0.0)) != 0.0 for e in entries):
        raise ParameterError("a softening flex spring (tendon stages) has no field map")
    names = [str(e["name"]) for e in entries]
    stiffness = np.stack([column(e["stiffness"][0], n) for e in entries], 1)
    damping = np.stack([column(e.get("damping", 0.0), n) for e in entries], 1)
    return flex_writes(model, names, stiffness, damping)
