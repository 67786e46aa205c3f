"""The virtual TEO's simulator-fit catalogue: which truth numbers the fit may change.

Nominal values are the shipped truth's. ``C`` is the payload point mass in the trunk that
reconciles the manual's masses with paper A's balance model.
"""

from __future__ import annotations

from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.fit_parameter import fit_parameter as _p

__all__ = ["FIT_CATALOGUE", "QUICK_FIT_PARAMETERS"]

FIT_CATALOGUE: tuple[FitParameter, ...] = (
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
"""Every fit parameter of the virtual TEO, by effect letter."""
QUICK_FIT_PARAMETERS: tuple[str, ...] = ("foot_softening_torque", "gear_stiffness")
"""A quick fit's two parameters: the gear stiffness sets the lean's linear compliance, the
foot softening torque the growth of its error with the target."""
