"""The virtual OP3's simulator-fit catalogue: which truth numbers the fit may change.

Nominal values are the shipped truth's (``robots/op3/data/truth.yaml``); the bounds span
what a kid-size servo drive of this class may have.
"""

from __future__ import annotations

from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.fit_parameter import fit_parameter as _p

__all__ = ["FIT_CATALOGUE", "QUICK_FIT_PARAMETERS"]

FIT_CATALOGUE: tuple[FitParameter, ...] = (
    _p("M", "pid_p_gain", "pid.kp", 18.9, (5.0, 75.0), "N·m/rad"),
    _p("M", "winding_resistance", "motor.resistance", 7.289, (3.6, 14.6), "Ω"),
    _p("M", "coulomb_friction", "friction.coulomb_link", 0.03, (0.003, 0.3), "N·m"),
    _p("I", "inductance", "motor.inductance", 1.0e-4, (2e-5, 1e-3), "H"),
    _p("G", "gear_stiffness", "gear.stiffness", 400.0, (100.0, 1600.0), "N·m/rad"),
    _p("G", "gear_damping", "gear.damping", 0.5, (0.05, 5.0), "N·m·s/rad"),
    _p("G", "gear_backlash", "gear.backlash", 0.00436, (4e-4, 0.02), "rad"),
    _p("F", "flex_stiffness", "flex[0,1].stiffness[0]", 600.0, (150.0, 2400.0), "N·m/rad"),
)
"""Every fit parameter of the virtual OP3, by effect letter."""
QUICK_FIT_PARAMETERS: tuple[str, ...] = ("pid_p_gain", "gear_stiffness")
"""A quick fit's two parameters: the servos' P gain sets the static error of a lean (the
servo is P-only); the gear, in series with it, the step's transient."""
