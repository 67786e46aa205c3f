"""Limits on one float, for the control ticks: no numpy, no objects (``min``/``max`` make some).

The walking controllers' ticks (:mod:`zmpkit.walking.dcm_stabiliser`,
:mod:`zmpkit.walking.zmp_observer`, :mod:`zmpkit.walking.heading_feedback`, the step
adjustment) limit Python floats with these.
"""

from __future__ import annotations

__all__ = ["clamp", "clip"]


def clamp(value: float, limit: float) -> float:
    """``value`` clamped to ±``limit`` (``limit`` >= 0)."""
    return -limit if value < -limit else (limit if value > limit else value)


def clip(value: float, lo: float, hi: float) -> float:
    """``value`` clipped to ``[lo, hi]``."""
    return lo if value < lo else (hi if value > hi else value)
