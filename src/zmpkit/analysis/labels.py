"""Names shown to a reader for the codes runs use (figure legends, titles, report tables).

One name per meaning, everywhere: the effect set ``none`` is the rigid robot, never
"uncompensated" (that is a compensation method's name, :data:`COMPENSATION_NAMES`).
"""

from __future__ import annotations

__all__ = ["COMPENSATION_NAMES", "EFFECT_NAMES", "compensation_name", "effects_name"]

EFFECT_NAMES = {"none": "rigid (effects off)", "all": "all effects"}
"""Effect-set codes (``--effects``) by their reader's name."""

COMPENSATION_NAMES = {"none": "uncompensated"}
"""Compensation-method codes (``--method``) whose reader's name differs from the code."""


def effects_name(effects: str) -> str:
    """The reader's name of an effect set: ``rigid (effects off)``, ``effects M,G``, ..."""
    return EFFECT_NAMES.get(effects, f"effects {effects}")


def compensation_name(method: str) -> str:
    """The reader's name of a compensation method: ``uncompensated`` for ``none``."""
    return COMPENSATION_NAMES.get(method, method)
