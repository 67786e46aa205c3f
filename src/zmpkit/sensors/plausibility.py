r"""A plausibility gate between the ankle F-T sensors and a ZMP feedback loop.

A closed loop that reads every F-T sample must not act on a sample a sensor could not have
measured. :class:`PlausibilityGate` turns one sample of both feet into the ZMP in one plane
[m] or None, and None is what a controller receives for a missing sample. A sample is
rejected when

- a component is not finite (NaN, inf: a dropped or corrupted packet);
- a component lies beyond the plausible limits :data:`MAX_PLAUSIBLE_FORCE_N`,
  :data:`MAX_PLAUSIBLE_MOMENT_NM` (the same limits the log readers apply);
- a force component reaches the sensor's range (``force_range_n``): a saturated channel
  reads its full scale, not the load;
- no foot is in contact (the ZMP is undefined);
- the ZMP jumps from the last accepted one by more than ``max_zmp_jump_m`` in one sample
  (a spike): :math:`|p_k - p_{last}| > \Delta p_{max}`. After ``max_rejected_in_row``
  rejected samples in a row the next sample is accepted again, so a real, sudden move of
  the ZMP does not lock the gate.

The gate counts its rejections by reason (:attr:`PlausibilityGate.rejected`). Per sample it
does float arithmetic only, no allocation beyond the ZMP's own tuple.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from zmpkit._validate import positive
from zmpkit.errors import ParameterError
from zmpkit.sensors.fast import DoubleSupportZmp

__all__ = [
    "FT_FORCE_RANGE_N",
    "MAX_PLAUSIBLE_FORCE_N",
    "MAX_PLAUSIBLE_MOMENT_NM",
    "REJECTION_REASONS",
    "PlausibilityGate",
    "PlausibilityLimits",
]

MAX_PLAUSIBLE_FORCE_N = 1.0e5
"""Largest force component a foot F-T sensor can plausibly report [N]: 100 kN, some 50
times the range of a humanoid's ankle sensor (a JR3 reads up to ~2 kN). Beyond it a value is
a unit, scaling or logging error, and a ZMP computed from it would be meaningless."""
MAX_PLAUSIBLE_MOMENT_NM = 1.0e4
"""Largest moment component a foot F-T sensor can plausibly report [N·m]: 10 kN·m (a JR3
reads up to ~200 N·m)."""
FT_FORCE_RANGE_N = 2000.0
"""Default force range of an ankle F-T sensor [N] (a JR3's ~2 kN): a channel reading this
much or more is taken as saturated."""
REJECTION_REASONS = ("non_finite", "implausible", "saturated", "no_contact", "spike")
"""Why a sample was rejected, the keys of :attr:`PlausibilityGate.rejected`."""


@dataclass(frozen=True)
class PlausibilityLimits:
    """What the gate accepts.

    Attributes:
        force_range_n: the sensor's force range; a component with ``|F| >=`` this is
            saturated [N].
        max_zmp_jump_m: largest change of the plane's ZMP from one accepted sample to the
            next [m].
        max_rejected_in_row: after this many rejected samples in a row the spike check
            accepts the next finite, in-range sample [-].
    """

    force_range_n: float = FT_FORCE_RANGE_N
    max_zmp_jump_m: float = 0.02
    max_rejected_in_row: int = 25

    def __post_init__(self) -> None:
        positive("force_range_n", self.force_range_n, "N")
        positive("max_zmp_jump_m", self.max_zmp_jump_m, "m")
        if isinstance(self.max_rejected_in_row, bool) or not (
            isinstance(self.max_rejected_in_row, int) and self.max_rejected_in_row >= 1
        ):
            raise ParameterError(
                f"max_rejected_in_row must be an integer >= 1, got {self.max_rejected_in_row!r}"
            )


class PlausibilityGate:
    """One F-T sample of both feet in, the plane's ZMP [m] or None out (module docstring).

    Args:
        zmp: the double-support ZMP of the robot's two sensor mounts.
        axis: 0 for the sagittal ZMP (x), 1 for the frontal ZMP (y).
        limits: what is accepted.
    """

    __slots__ = ("_axis", "_in_row", "_last", "_limits", "_zmp", "rejected")

    def __init__(
        self, zmp: DoubleSupportZmp, axis: int, limits: PlausibilityLimits | None = None
    ) -> None:
        if axis not in (0, 1):
            raise ParameterError(f"axis must be 0 (x, sagittal) or 1 (y, frontal), got {axis!r}")
        self._zmp, self._axis = zmp, axis
        self._limits = limits or PlausibilityLimits()
        self._last = math.nan
        self._in_row = 0
        self.rejected = dict.fromkeys(REJECTION_REASONS, 0)

    def __call__(self, right_wrench: Sequence[float], left_wrench: Sequence[float]) -> float | None:
        """The ZMP in the gate's plane [m], or None if the sample is rejected.

        Args:
            right_wrench: right sensor-frame wrench (F_x, F_y, F_z, τ_x, τ_y, τ_z) [N, N·m].
            left_wrench: left sensor-frame wrench, likewise.
        """
        reason = _wrench_fault(right_wrench, self._limits.force_range_n) or _wrench_fault(
            left_wrench, self._limits.force_range_n
        )
        if reason:
            self._reject(reason)
            return None
        both = self._zmp.compute(right_wrench, left_wrench)
        if both is None:
            self._reject("no_contact")
            return None
        value = both[self._axis]
        jump = abs(value - self._last)  # NaN (no sample yet) compares False
        if jump > self._limits.max_zmp_jump_m and self._in_row < self._limits.max_rejected_in_row:
            self._reject("spike")
            return None
        self._last, self._in_row = value, 0
        return value

    def _reject(self, reason: str) -> None:
        self.rejected[reason] += 1
        self._in_row += 1


def _wrench_fault(wrench: Sequence[float], force_range_n: float) -> str:
    """Why one sensor's wrench is rejected, or ``""`` if it is plausible."""
    for j, value in enumerate(wrench):
        if not math.isfinite(value):
            return "non_finite"
        limit = MAX_PLAUSIBLE_FORCE_N if j < 3 else MAX_PLAUSIBLE_MOMENT_NM
        if abs(value) > limit:
            return "implausible"
        if j < 3 and abs(value) >= force_range_n:
            return "saturated"
    return ""
