r"""The simulator-fit catalogue of a robot whose truth is a servo truth file (a user's robot).

A built-in robot lists its fit parameters by hand, with bounds from what its kind of drive may
have. A user's ``robot.yaml`` with ``truth:`` (the layout of :mod:`zmpkit.robots.servo_truth`)
gets one derived from its truth: each number below that the file gives as a positive value
becomes a parameter, searched in log space over a factor of four either side of it,

.. math:: v \in [v_0 / 4,\ 4 v_0],

the span within which a datasheet value and the real drive usually agree (the built-in
kid-size robot's hand-set bounds for its P gain, gear and flex stiffness are the same). A zero
(an unused integral gain, no backlash) stays out: the fit cannot tell a log-scaled factor of
nothing. Flexible links whose first stiffness is the same share one parameter; otherwise each
link has its own.

A voltage drive (``motor.drive: voltage``, a PWM servo) also fits its winding resistance
``R``: its PID drives the winding voltage, so ``R`` sets both the back-EMF damping
:math:`N^2 K^2 / R` and the stall torque :math:`N K V / R` (a current drive's ``R`` only
bounds its voltage, and its back-EMF damping is ``friction.viscous_motor``). The simulated
robot of every candidate keeps the truth's drive: the fit changes numbers of the truth file
and loads it as the truth is loaded.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from zmpkit.robots.fit_parameter import FitParameter, fit_parameter

__all__ = ["SERVO_FIT_FACTOR", "SERVO_QUICK_PARAMETERS", "servo_fit_catalogue"]

SERVO_FIT_FACTOR = 4.0
"""Each bound is the truth's value divided or multiplied by this [-]."""

_ENTRIES: tuple[tuple[str, str, str, str], ...] = (
    ("M", "pid_p_gain", "pid.kp", "N·m/rad"),
    ("M", "pid_i_gain", "pid.ki", "N·m/(rad·s)"),
    ("M", "pid_d_gain", "pid.kd", "N·m·s/rad"),
    ("M", "winding_resistance", "motor.resistance", "Ω"),
    ("M", "back_emf_damping", "friction.viscous_motor", "N·m·s/rad"),
    ("M", "coulomb_friction", "friction.coulomb_link", "N·m"),
    ("I", "inductance", "motor.inductance", "H"),
    ("G", "gear_stiffness", "gear.stiffness", "N·m/rad"),
    ("G", "gear_damping", "gear.damping", "N·m·s/rad"),
    ("G", "gear_backlash", "gear.backlash", "rad"),
)
"""(effect, name, path in the truth YAML, unit) of every candidate but the flex links."""
VOLTAGE_DRIVE_ONLY = ("motor.resistance",)
"""Candidates of a voltage drive only (module docstring)."""

SERVO_QUICK_PARAMETERS: tuple[str, ...] = ("pid_p_gain", "gear_stiffness")
"""A quick fit's parameters, where the truth has them: the servo's gain and the gear in
series with it, which set a balance step's static error and transient."""


def _value(doc: Mapping[str, Any], path: str) -> float | None:
    section, _, key = path.partition(".")
    block = doc.get(section)
    if not isinstance(block, Mapping):
        return None
    value = block.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


def _entry(effect: str, name: str, path: str, nominal: float, unit: str) -> FitParameter:
    bounds = (nominal / SERVO_FIT_FACTOR, nominal * SERVO_FIT_FACTOR)
    return fit_parameter(effect, name, path, nominal, bounds, unit)


def _flex(doc: Mapping[str, Any]) -> list[FitParameter]:
    links = doc.get("flex")
    if not isinstance(links, Sequence) or isinstance(links, str):
        return []
    firsts: list[tuple[int, str, float]] = []
    for i, link in enumerate(links):
        stiffness = link.get("stiffness") if isinstance(link, Mapping) else None
        if not (isinstance(stiffness, Sequence) and stiffness):
            continue
        first = stiffness[0]
        if isinstance(first, int | float) and not isinstance(first, bool) and first > 0.0:
            firsts.append((i, str(link.get("name", i)), float(first)))
    if not firsts:
        return []
    if len({k for _, _, k in firsts}) == 1:
        items = ",".join(str(i) for i, _, _ in firsts)
        path = f"flex[{items}].stiffness[0]"
        return [_entry("F", "flex_stiffness", path, firsts[0][2], "N·m/rad")]
    return [
        _entry("F", f"flex_stiffness_{name}", f"flex[{i}].stiffness[0]", k, "N·m/rad")
        for i, name, k in firsts
    ]


def servo_fit_catalogue(doc: Mapping[str, Any]) -> tuple[FitParameter, ...]:
    """The fit parameters of a servo truth document (module docstring).

    Args:
        doc: the truth YAML, parsed.

    Returns:
        One :class:`FitParameter` per positive candidate value, effects M, I, G, F in order.
    """
    motor = doc.get("motor")
    voltage = isinstance(motor, Mapping) and motor.get("drive") == "voltage"
    catalogue = []
    for effect, name, path, unit in _ENTRIES:
        if path in VOLTAGE_DRIVE_ONLY and not voltage:
            continue
        value = _value(doc, path)
        if value is not None and value > 0.0:
            catalogue.append(_entry(effect, name, path, value, unit))
    catalogue += _flex(doc)
    return tuple(catalogue)
