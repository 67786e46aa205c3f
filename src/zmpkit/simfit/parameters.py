r"""Fit parameters: what the evolutionary fit may change in a robot's truth file, and how.

A :class:`FitParameter` names one number (or one number shared by several entries) of the
truth YAML by its path, with a nominal value, bounds and a unit. The optimiser works in
normalised coordinates ``u`` in [0, 1]:

.. math::
    v = v_{lo} + u (v_{hi} - v_{lo}) \quad \text{or, with ``log_scale``,} \quad
    v = v_{lo} (v_{hi} / v_{lo})^u,

so every parameter has the same scale for CMA-ES whatever its unit.

:func:`default_parameters` gives the catalogue per robot and effect letter (paper B §II:
M motor + PID, I inductance, G gears, F flexible links, S sensors; plus ``C`` for the
CAD-vs-real mass and CoM: TEO's payload point mass in the trunk, NAO's real torso link mass
and forward CoM).

Nominal values are the shipped truth's, except NAO's ``C``: there the nominal is the design
(the URDF torso, what the IK and the walking pattern use), the fit's natural starting point;
the shipped truth's torso is heavier and its CoM further forward. NAO's torso CoM height
(``torso.com_m[2]``) is left out: it moves the CoM height by under a millimetre and walking
data barely see it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = [
    "FIT_LETTERS",
    "ROBOTS",
    "FitParameter",
    "ParameterValues",
    "default_parameters",
    "from_unit",
    "parse_fit_effects",
    "to_unit",
]

ROBOTS: tuple[str, ...] = ("nao", "teo")
"""Robots whose simulator can be fitted."""
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


def from_unit(parameters: Sequence[FitParameter], u: Sequence[float]) -> NDArray[np.float64]:
    """Values [units] of a normalised vector ``u``."""
    return np.array([p.from_unit(x) for p, x in zip(parameters, u, strict=True)])


def to_unit(parameters: Sequence[FitParameter], values: Sequence[float]) -> NDArray[np.float64]:
    """Normalised vector of ``values`` [units]."""
    return np.array([p.to_unit(v) for p, v in zip(parameters, values, strict=True)])


def _p(
    effect: str,
    name: str,
    path: str,
    nominal: float,
    bounds: tuple[float, float],
    unit: str,
    log: bool = True,
) -> FitParameter:
    return FitParameter(name, path, nominal, bounds[0], bounds[1], unit, log, effect)


_NAO: tuple[FitParameter, ...] = (
    _p("M", "pid_gain_scale", "stiffness", 0.7, (0.35, 1.0), "-"),
    _p("M", "pid_d_gain", "pid_volts.d", 9.81, (2.0, 40.0), "V·s/rad"),
    _p("M", "coulomb_friction", "friction.coulomb_link", 0.05, (0.005, 0.5), "N·m"),
    _p("I", "inductance", "motor.inductance", 3.09e-4, (5e-5, 2e-3), "H"),
    _p("G", "gear_stiffness", "gear.stiffness", 1200.0, (300.0, 5000.0), "N·m/rad"),
    _p("G", "gear_damping", "gear.damping", 1.0, (0.1, 10.0), "N·m·s/rad"),
    _p("G", "gear_backlash", "gear.backlash", 0.001, (1e-4, 0.01), "rad"),
    _p(
        "F",
        "flex_pitch_stiffness",
        "flex[0,1,2,3].stiffness[0]",
        1800.0,
        (400.0, 8000.0),
        "N·m/rad",
    ),
    _p("F", "flex_roll_stiffness", "flex[4,5].stiffness[0]", 2400.0, (500.0, 10000.0), "N·m/rad"),
    _p("S", "ft_offset_fz_right", "sensors.ft_offset.right[2]", 1.5, (-5.0, 5.0), "N", False),
    _p("S", "ft_offset_fz_left", "sensors.ft_offset.left[2]", 1.2, (-5.0, 5.0), "N", False),
    # Nominal = the URDF torso (robots/nao/geometry.py TORSO), the design. Bounds: the
    # open-loop walk with every effect on falls from about 1.25 kg, or 1.175 kg at x -0.019 m.
    _p("C", "torso_mass", "torso.mass_kg", 1.04956, (0.85, 1.25), "kg", False),
    _p("C", "torso_com_x", "torso.com_m[0]", -0.00413, (-0.02, 0.03), "m", False),
)
_TEO: tuple[FitParameter, ...] = (
    _p("M", "pid_kp", "pid.kp_link", 30000.0, (5000.0, 150000.0), "N·m/rad"),
    _p("M", "pid_kd", "pid.kd_link", 300.0, (30.0, 3000.0), "N·m·s/rad"),
    _p("M", "coulomb_friction", "friction.coulomb_link", 1.5, (0.1, 10.0), "N·m"),
    _p("I", "inductance_402686", "motor_types.maxon_402686.inductance", 1e-3, (1e-4, 1e-2), "H"),
    _p("G", "gear_stiffness", "gear.stiffness", 40000.0, (8000.0, 200000.0), "N·m/rad"),
    _p("G", "gear_damping", "gear.damping", 40.0, (4.0, 400.0), "N·m·s/rad"),
    _p("F", "foot_softening_torque", "flex[0,1].softening_torque", 0.65, (0.1, 5.0), "N·m"),
    _p("F", "foot_pitch_stiffness", "flex[0,1].stiffness[0]", 200000.0, (20000.0, 1e6), "N·m/rad"),
    _p(
        "F",
        "trunk_pitch_stiffness",
        "flex[6].stiffness[0]",
        60000.0,
        (10000.0, 300000.0),
        "N·m/rad",
    ),
    _p("S", "ft_offset_fz_right", "sensors.ft_offset.right[2]", 3.0, (-20.0, 20.0), "N", False),
    _p("S", "ft_offset_fz_left", "sensors.ft_offset.left[2]", -2.0, (-20.0, 20.0), "N", False),
    _p("C", "payload_mass", "payload.mass_kg", 6.66, (0.0, 15.0), "kg", False),
    _p("C", "payload_height", "payload.position_m[2]", 0.1222, (-0.1, 0.4), "m", False),
)
_CATALOGUE = {"nao": _NAO, "teo": _TEO}


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


def default_parameters(
    robot: str, effects: str, names: Sequence[str] | None = None
) -> tuple[FitParameter, ...]:
    """The catalogue's parameters of ``robot`` for the effect letters ``effects``.

    Args:
        robot: one of :data:`ROBOTS`.
        effects: letters such as ``"M,G"``.
        names: keep only these parameter names (in this order); None keeps all.

    Raises:
        ParameterError: on an unknown robot, letter or name, or an effect without parameters.
    """
    if robot not in _CATALOGUE:
        raise ParameterError(f"robot must be one of {', '.join(ROBOTS)}; got {robot!r}")
    letters = parse_fit_effects(effects)
    chosen = [p for p in _CATALOGUE[robot] if p.effect in letters]
    empty = [x for x in letters if not any(p.effect == x for p in chosen)]
    if empty:
        have = sorted({p.effect for p in _CATALOGUE[robot]})
        raise ParameterError(
            f"{robot} has no fit parameters for effect {', '.join(empty)}; it has: {have}"
        )
    if names is None:
        return tuple(chosen)
    by_name = {p.name: p for p in chosen}
    missing = [n for n in names if n not in by_name]
    if missing:
        raise ParameterError(
            f"unknown fit parameters {missing} for {robot} effects {effects!r}; "
            f"valid: {sorted(by_name)}"
        )
    return tuple(by_name[n] for n in names)
