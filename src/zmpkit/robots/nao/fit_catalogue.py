"""The virtual NAO's simulator-fit catalogue: which truth numbers the fit may change.

Nominal values are the shipped truth's, except ``C``: there the nominal is the design (the
URDF torso, what the IK and the walking pattern use), the fit's natural starting point; the
shipped truth's torso is heavier and its CoM further forward. The torso CoM height
(``torso.com_m[2]``) is left out: it moves the CoM height by under a millimetre and walking
data barely see it.
"""

from __future__ import annotations

from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.fit_parameter import fit_parameter as _p

__all__ = ["FIT_CATALOGUE", "QUICK_FIT_PARAMETERS"]

FIT_CATALOGUE: tuple[FitParameter, ...] = (
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
"""Every fit parameter of the virtual NAO, by effect letter."""
QUICK_FIT_PARAMETERS: tuple[str, ...] = ("pid_gain_scale", "gear_stiffness")
"""A quick fit's two parameters: the PID gain scale sets the joint tracking error (the
encoders see it directly); the gear stiffness the trunk oscillation."""
