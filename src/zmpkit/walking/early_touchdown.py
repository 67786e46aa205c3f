r"""A swing foot that meets the floor before its planned touchdown stops descending there.

The plan lowers a swing sole to the floor on its own clock. When the robot leans towards the
swing side (a push, a soft gear, a sideways step), the sole meets the floor early, still
commanded ``h`` above it; driving the leg on down the last ``h`` lifts that side of the robot
off its stance foot. Measured on the built-in walker's sideways walk (0.05 m/s, motor and
gear effects, the DCM walk): the first swing sole touched about 50 ms early, took 122 N (2.3
times the robot's weight) within a tick and left the floor again while the plan moved the
ZMP onto it, and from then on the measured ZMP sat at the outer edge of each stance sole
until the robot rolled over at 3.7 s.

Each control tick, for each foot: once its F-T sensor reads a vertical force at the contact
threshold while the plan still has it descending in the air (planned height above the
plan's floor level ``z_0`` and below the last frame's), its commanded height is held at the
last commanded one, ``h_c``; from the planned touchdown on it returns to the plan linearly
over the release time ``T_r``:

.. math:: z_k = \begin{cases} h_c & \text{before the planned touchdown} \\
    z^{plan}_k + (h_c - z_0)\,\max\!\big(0, 1 - (k - k_{td})\,T / T_r\big) & \text{after.}
    \end{cases}

A foot that bounces off the floor again keeps its held height: the sole is not driven down
into the floor it met. The tick writes floats into the IK's targets (no numpy object).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError

__all__ = ["DEFAULT_RELEASE_S", "EarlyTouchdown"]

DEFAULT_RELEASE_S = 0.1
"""T_r: how long a held sole takes to return to the plan after its planned touchdown [s]."""

_IN_AIR_M = 1e-4
"""A planned sole this far above the plan's floor level is in the air [m]."""


class EarlyTouchdown:
    """Holds the commanded height of a swing sole that touched down early (module docstring).

    Args:
        planned_heights_m: per foot (in the force's order), the plan's sole height of each
            frame [m], shape (N,) each; read only.
        commanded_heights_m: per foot, the IK's sole-height targets of each frame [m], shape
            (N,) each (views into the targets); the tick writes the current frame's.
        period_s: the control period T [s].
        release_s: T_r [s].
    """

    def __init__(
        self,
        planned_heights_m: list[NDArray[np.float64]],
        commanded_heights_m: list[NDArray[np.float64]],
        period_s: float,
        release_s: float = DEFAULT_RELEASE_S,
    ) -> None:
        if len(planned_heights_m) != len(commanded_heights_m):
            raise ParameterError("EarlyTouchdown needs a planned and a commanded height row a foot")
        self.period_s = _validate.positive("period_s", period_s, "s")
        self.release_s = _validate.positive("release_s", release_s, "s")
        self._feet = tuple(
            (i, plan, commanded, float(np.min(plan)))
            for i, (plan, commanded) in enumerate(
                zip(planned_heights_m, commanded_heights_m, strict=True)
            )
        )
        n = len(self._feet)
        self._held_m = [math.nan] * n  # h_c, NaN: not held
        self._touchdown = [-1] * n  # the planned touchdown's frame once reached, -1 before
        self.holds = 0
        """How many early touchdowns were held so far [-]."""

    def update(self, frame: int, force_z_n: NDArray[np.float64], threshold_n: float) -> None:
        """Write frame ``frame``'s commanded sole heights from the forces of the frame before.

        Args:
            frame: the frame whose targets the IK solves next [-].
            force_z_n: each foot's vertical force in the world [N], shape (F,).
            threshold_n: the contact threshold [N].
        """
        held, touchdown, release = self._held_m, self._touchdown, self.release_s
        for i, plan, commanded, floor in self._feet:
            planned = plan.item(frame)
            in_air = planned > floor + _IN_AIR_M
            h = held[i]
            if h != h:  # not held (NaN): hold a descending sole that carries a load
                if (
                    in_air
                    and frame > 0
                    and planned < plan.item(frame - 1)
                    and force_z_n.item(i) >= threshold_n
                ):
                    h = commanded.item(frame - 1)
                    held[i] = h
                    self.holds += 1
                else:
                    continue
            if in_air and touchdown[i] < 0:
                commanded[frame] = h
                continue
            if touchdown[i] < 0:
                touchdown[i] = frame
            left = 1.0 - (frame - touchdown[i]) * self.period_s / release
            if left <= 0.0 or in_air:  # released, or the next swing began
                held[i], touchdown[i] = math.nan, -1
                continue
            commanded[frame] = planned + (h - floor) * left
