"""A ZMP-step trial (paper A §4.1, Fig. 14): the measured ZMP answering a step of its target.

The robot's ZMP target steps at :math:`t_{step}`; the ankle F-T sensors measure the ZMP
before and after it. Its settled value is :func:`~zmpkit.signals.steady_state.steady_state`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit._validate import finite, finite_array
from zmpkit.errors import ParameterError
from zmpkit.models.lti import _increasing_times

__all__ = ["PLANES", "StepTrial"]

FloatArray = NDArray[np.float64]


PLANES = ("sagittal", "frontal")
"""Valid values of :attr:`StepTrial.plane`: sagittal (x–z, ZMP x) and frontal (y–z, ZMP y)."""


@dataclass(frozen=True, eq=False)
class StepTrial:
    r"""One ZMP-step trial in one plane.

    Attributes:
        time: sample times [s], strictly increasing, shape (N,).
        zmp_measured: ZMP from the F-T sensors in this plane [m], shape (N,).
        zmp_ref: the ZMP target after the step [m].
        t_step: time of the step [s], within ``[time[0], time[-1])``.
        plane: ``"sagittal"`` or ``"frontal"``.
        zmp_commanded: the LIPM-expected ZMP :math:`l\sin\theta` of the commanded angle [m];
            ``None`` means ``zmp_ref`` (the classic open-loop experiment, θ = asin(x_ref/l)).
        zmp_commanded_before: the same before the step [m]; 0 for a robot starting upright.
    """

    time: FloatArray
    zmp_measured: FloatArray
    zmp_ref: float
    t_step: float
    plane: str = "sagittal"
    zmp_commanded: float | None = None
    zmp_commanded_before: float = 0.0

    def __post_init__(self) -> None:
        time = _increasing_times("time", self.time)
        zmp = finite_array("zmp_measured", self.zmp_measured, (time.size,))
        for array in (time, zmp):
            array.setflags(write=False)
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "zmp_measured", zmp)
        object.__setattr__(self, "zmp_ref", finite("zmp_ref", self.zmp_ref))
        t0 = finite("t_step", self.t_step)
        if not time[0] <= t0 < time[-1]:
            raise ParameterError(
                f"t_step must lie in [time[0], time[-1]) = [{time[0]}, {time[-1]}) s, got {t0} s"
            )
        object.__setattr__(self, "t_step", t0)
        if self.plane not in PLANES:
            raise ParameterError(f"plane must be one of {PLANES}, got {self.plane!r}")
        if self.zmp_commanded is not None:
            object.__setattr__(self, "zmp_commanded", finite("zmp_commanded", self.zmp_commanded))
        before = finite("zmp_commanded_before", self.zmp_commanded_before)
        object.__setattr__(self, "zmp_commanded_before", before)

    @property
    def x_cmd(self) -> float:
        """The commanded (LIPM-expected) ZMP after the step [m]: the error model's input."""
        return self.zmp_ref if self.zmp_commanded is None else self.zmp_commanded
