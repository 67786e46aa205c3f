r"""One number of a robot's truth file that the simulator fit may change, with its bounds.

A :class:`FitParameter` names one number (or one number shared by several entries) of the
truth YAML by its path, with a nominal value, bounds and a unit. The optimiser works in
normalised coordinates ``u`` in [0, 1]:

.. math::
    v = v_{lo} + u (v_{hi} - v_{lo}) \quad \text{or, with ``log_scale``,} \quad
    v = v_{lo} (v_{hi} / v_{lo})^u,

so every parameter has the same scale for CMA-ES whatever its unit. Each robot lists its own
(its fit catalogue, :class:`~zmpkit.robots.robot.FitSpec`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit.errors import ParameterError

__all__ = ["FitParameter", "fit_parameter"]


@dataclass(frozen=True)
class FitParameter:
    """One fitted number of the truth YAML.

    Attributes:
        name: short name used in tables and files, e.g. ``"gear_stiffness"``.
        path: where it sits in the truth YAML: keys joined by dots, list items in brackets;
            ``[0,1]`` or ``[*]`` sets several items to the same value, e.g.
            ``"flex[0,1].softening_torque"``.
        nominal: the value the fit starts from [unit].
        lower: lower bound [unit].
        upper: upper bound [unit].
        unit: unit of the value, e.g. ``"N·m/rad"``.
        log_scale: search in log space (for positive values spanning a ratio).
        effect: the effect letter it belongs to.
    """

    name: str
    path: str
    nominal: float
    lower: float
    upper: float
    unit: str
    log_scale: bool = False
    effect: str = ""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.lower) and math.isfinite(self.upper)):
            raise ParameterError(f"FitParameter {self.name}: bounds must be finite")
        if not self.lower < self.upper:
            raise ParameterError(
                f"FitParameter {self.name}: need lower < upper, got [{self.lower}, {self.upper}]"
            )
        if not self.lower <= self.nominal <= self.upper:
            raise ParameterError(
                f"FitParameter {self.name}: nominal {self.nominal} {self.unit} is outside "
                f"[{self.lower}, {self.upper}]"
            )
        if self.log_scale and self.lower <= 0.0:
            raise ParameterError(
                f"FitParameter {self.name}: log_scale needs lower > 0, got {self.lower}"
            )

    def from_unit(self, u: float) -> float:
        """The value [unit] at normalised coordinate ``u`` (clipped to [0, 1])."""
        u = min(1.0, max(0.0, float(u)))
        if self.log_scale:
            return self.lower * (self.upper / self.lower) ** u
        return self.lower + u * (self.upper - self.lower)

    def to_unit(self, value: float) -> float:
        """The normalised coordinate [-] of ``value`` [unit]."""
        if self.log_scale:
            return math.log(value / self.lower) / math.log(self.upper / self.lower)
        return (value - self.lower) / (self.upper - self.lower)


def fit_parameter(
    effect: str,
    name: str,
    path: str,
    nominal: float,
    bounds: tuple[float, float],
    unit: str,
    log: bool = True,
) -> FitParameter:
    """A catalogue entry: :class:`FitParameter` with its effect letter first.

    Args:
        effect: effect letter (``"M"``, ``"I"``, ``"G"``, ``"F"``, ``"S"``, ``"C"``).
        name: short name.
        path: path in the truth YAML.
        nominal: starting value [unit].
        bounds: ``(lower, upper)`` [unit].
        unit: the unit.
        log: search in log space.
    """
    return FitParameter(name, path, nominal, bounds[0], bounds[1], unit, log, effect)
