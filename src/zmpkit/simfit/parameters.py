"""Fit parameters: what the evolutionary fit may change in a robot's truth file, and how.

A :class:`~zmpkit.robots.fit_parameter.FitParameter` names one number of the truth YAML with
its nominal value, bounds and unit; the optimiser works in normalised coordinates in [0, 1]
(:func:`from_unit`, :func:`to_unit`).

:func:`default_parameters` gives a robot's catalogue (its
:attr:`~zmpkit.robots.robot.FitSpec.catalogue`) per effect letter (paper B §II: M motor +
PID, I inductance, G gears, F flexible links, S sensors; plus ``C`` for the CAD-vs-real mass
and CoM). Nominal values are the shipped truth's unless the robot's catalogue says otherwise.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.robot import Robot

__all__ = [
    "FIT_LETTERS",
    "FitParameter",
    "ParameterValues",
    "default_parameters",
    "from_unit",
    "nominal_values",
    "parse_fit_effects",
    "robot_catalogue",
    "to_unit",
]

FIT_LETTERS: dict[str, str] = {
    "M": "motor and PID",
    "I": "winding inductance",
    "G": "gear stiffness, damping, backlash",
    "F": "flexible links",
    "S": "F-T sensor offsets",
    "C": "mass and CoM (CAD vs real)",
}
"""Effect letters that carry fit parameters."""

ParameterValues: TypeAlias = Sequence[float] | NDArray[np.float64]
"""One value per fitted parameter [its unit]: a list, or an array as the optimiser gives it."""


def from_unit(parameters: Sequence[FitParameter], u: Sequence[float]) -> NDArray[np.float64]:
    """Values [units] of a normalised vector ``u``."""
    return np.array([p.from_unit(x) for p, x in zip(parameters, u, strict=True)])


def nominal_values(parameters: Sequence[FitParameter]) -> NDArray[np.float64]:
    """The catalogue's nominal value of each parameter [units]."""
    return np.array([p.nominal for p in parameters], dtype=np.float64)


def to_unit(parameters: Sequence[FitParameter], values: Sequence[float]) -> NDArray[np.float64]:
    """Normalised vector of ``values`` [units]."""
    return np.array([p.to_unit(v) for p, v in zip(parameters, values, strict=True)])


def parse_fit_effects(text: str) -> tuple[str, ...]:
    """Effect letters from ``"M,G"`` (case-insensitive, spaces ignored), in catalogue order.

    Raises:
        ParameterError: on an empty list or an unknown letter, naming the valid ones.
    """
    letters = {x.strip().upper() for x in str(text).split(",") if x.strip()}
    unknown = sorted(letters - set(FIT_LETTERS))
    if unknown or not letters:
        valid = ", ".join(f"{k} ({v})" for k, v in FIT_LETTERS.items())
        raise ParameterError(
            f"effects to fit must be comma-separated letters from: {valid}; got {text!r}"
        )
    return tuple(k for k in FIT_LETTERS if k in letters)


def robot_catalogue(robot: Robot) -> tuple[FitParameter, ...]:
    """Every fit parameter of ``robot``.

    Raises:
        ParameterError: on a robot without a fit catalogue.
    """
    return robot.require_fit().catalogue


def default_parameters(
    robot: Robot, effects: str, names: Sequence[str] | None = None
) -> tuple[FitParameter, ...]:
    """The catalogue's parameters of ``robot`` for the effect letters ``effects``.

    Args:
        robot: a robot with a fit catalogue.
        effects: letters such as ``"M,G"``.
        names: keep only these parameter names (in this order); None keeps all.

    Raises:
        ParameterError: on a robot without a fit catalogue, an unknown letter or name, or an
            effect without parameters.
    """
    catalogue = robot_catalogue(robot)
    letters = parse_fit_effects(effects)
    chosen = [p for p in catalogue if p.effect in letters]
    empty = [x for x in letters if not any(p.effect == x for p in chosen)]
    if empty:
        have = sorted({p.effect for p in catalogue})
        raise ParameterError(
            f"{robot.source} has no fit parameters for effect {', '.join(empty)}; it has: {have}"
        )
    if names is None:
        return tuple(chosen)
    by_name = {p.name: p for p in chosen}
    missing = [n for n in names if n not in by_name]
    if missing:
        raise ParameterError(
            f"unknown fit parameters {missing} for {robot.source} effects {effects!r}; "
            f"valid: {sorted(by_name)}"
        )
    return tuple(by_name[n] for n in names)
