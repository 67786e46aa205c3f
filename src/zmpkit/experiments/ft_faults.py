"""Sensor faults injected into the F-T readings a feedback controller reads.

``zmpkit balance --fault KIND`` (repeatable) shows that the ZMP feedback loop survives the
faults a real ankle F-T sensor shows. The faults come in bursts: from :attr:`FtFaults.start_s`
after the step, every :attr:`FtFaults.period_s`, for :attr:`FtFaults.duration_s`; with
several kinds the bursts take them in turn. Per kind, during a burst:

- ``dropout``: the sample does not arrive (the reader gets nothing);
- ``spike``: an impulsive moment :attr:`FtFaults.spike_moment_nm` is added to the right
  sensor's τ_x and τ_y (a few cm of ZMP, within the sensor's range);
- ``nan``: every component of the right sensor reads NaN (a corrupted packet);
- ``saturation``: the right sensor's force channels read the sensor's full scale
  :attr:`FtFaults.force_range_n` with their sign (a saturated amplifier).

Only the controller's reading is corrupted: the recorded dataset (the logger's channel) keeps
the clean samples, so no NaN is ever written and the evaluation measures what the robot did.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit._validate import positive
from zmpkit.errors import ParameterError
from zmpkit.sensors.plausibility import FT_FORCE_RANGE_N

__all__ = ["FAULT_KINDS", "FtFaults"]

FAULT_KINDS = ("dropout", "spike", "nan", "saturation")
"""The sensor faults that can be injected."""


@dataclass(frozen=True)
class FtFaults:
    """Bursts of F-T faults after the step (module docstring).

    Attributes:
        kinds: fault kinds, each one of :data:`FAULT_KINDS`, taken in turn per burst.
        start_s: first burst, after the step [s].
        period_s: time from one burst's start to the next [s].
        duration_s: length of a burst [s], at most ``period_s``.
        spike_moment_nm: the moment a spike adds [N·m].
        force_range_n: the sensor's force range, what a saturated channel reads [N].
    """

    kinds: tuple[str, ...]
    start_s: float = 1.0
    period_s: float = 1.0
    duration_s: float = 0.1
    spike_moment_nm: float = 40.0
    force_range_n: float = FT_FORCE_RANGE_N

    def __post_init__(self) -> None:
        if not self.kinds:
            raise ParameterError(f"fault kinds must name at least one of {', '.join(FAULT_KINDS)}")
        for kind in self.kinds:
            if kind not in FAULT_KINDS:
                raise ParameterError(
                    f"fault kind must be one of {', '.join(FAULT_KINDS)}; got {kind!r}"
                )
        positive("start_s", self.start_s, "s")
        if not 0.0 < positive("duration_s", self.duration_s, "s") <= self.period_s:
            raise ParameterError(
                f"duration_s must lie in (0, period_s = {self.period_s:g}] s, "
                f"got {self.duration_s:g} s"
            )
        positive("spike_moment_nm", self.spike_moment_nm, "N·m")
        positive("force_range_n", self.force_range_n, "N")

    def kind_at(self, time_since_step_s: float) -> str:
        """The fault acting at this time after the step, or ``""`` if none [s]."""
        since = time_since_step_s - self.start_s
        if since < 0.0:
            return ""
        burst = math.floor(since / self.period_s)
        if since - burst * self.period_s >= self.duration_s:
            return ""
        return self.kinds[burst % len(self.kinds)]

    def apply(self, time_since_step_s: float, right: list[float]) -> bool:
        """Corrupt the right sensor's reading in place; False if the sample is dropped.

        Args:
            time_since_step_s: time after the step [s].
            right: the right sensor's wrench (F_x, F_y, F_z, τ_x, τ_y, τ_z) [N, N·m], six
                floats, changed in place.
        """
        kind = self.kind_at(time_since_step_s)
        if kind == "dropout":
            return False
        if kind == "spike":
            right[3] += self.spike_moment_nm
            right[4] += self.spike_moment_nm
        elif kind == "nan":
            right[:] = [math.nan] * 6
        elif kind == "saturation":
            for j in range(3):
                right[j] = math.copysign(self.force_range_n, right[j])
        return True
