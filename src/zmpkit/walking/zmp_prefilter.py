r"""What a walking observer reads of the measured ZMP: less what the plan predicts, low-passed.

The ZMP/IP observer (:mod:`zmpkit.walking.zmp_observer`) corrects its cart-table state by the
measured ZMP. Two things in that measurement are not disturbances for it to fight:

- **the legs' own dynamics**: the multibody robot's ZMP differs from the cart table's on the
  planned motion itself (:func:`~zmpkit.walking.multibody_zmp.expected_zmp_offset`,
  :math:`\Delta_k`; ±4 cm along x every step on the default walking robot at 0.2 m/s),
  which the design model predicts before the walk starts;
- **landings**: a foot landing and rocking on stiff contacts moves the F-T ZMP by
  centimetres from one 10 ms frame to the next, faster than the CoM can answer.

So the observer reads :math:`y_k = \mathrm{LP}(p^{meas}_k - \Delta_k)`, a first-order
low-pass at :data:`ZMP_FILTER_HZ`,
:math:`y_k = y_{k-1} + \alpha (p^{meas}_k - \Delta_k - y_{k-1})`,
:math:`\alpha = T / (T + 1 / (2\pi f_c))`, restarted at the first reading after a frame
without contact (NaN, which it passes on).

Measured on the default walking robot, rigid (every effect off, 0.2 m/s, 0.5 s steps,
10 s), the closed-loop walk's step-frequency trunk oscillation against the open-loop
walk's 0.0027 rad: 3.2 times reading the raw ZMP, 1.85 times less :math:`\Delta`, 1.04
times low-passed only, 0.67 times both. The cut-off was chosen on that one walk (10 Hz,
before 5 and 2 Hz were tried: 0.0016 and 0.0024 rad) and judged on the 116 cases of
``zmpkit walk sweep`` (all effects, seed 0), none of them used to choose it: the ZMP/IP
walk's falls 47 → 39 (10 N pushes 2 → 0 of 32, 20 N 16 → 10, 30 N 29 → 29), none
unpushed before or after; less :math:`\Delta` alone, 43. The same reading in the DCM walk's
observer made 5 of its first 16 (unpushed) cases fall sideways: it reads the raw ZMP.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["ZMP_FILTER_HZ", "ZmpPrefilter"]

ZMP_FILTER_HZ = 10.0
"""Cut-off of the low-pass on the ZMP the observer reads [Hz] (module docstring)."""


class ZmpPrefilter:
    r"""The ZMP an observer reads each period (module docstring).

    Args:
        period_s: the control period :math:`T` [s].
        expected_zmp_offset_in_world: :math:`\Delta_k` per period [m], shape (N, 2); past
            the end its last row; None: nothing subtracted.
        cutoff_hz: :math:`f_c` [Hz]; None: no low-pass.
    """

    def __init__(
        self,
        period_s: float,
        expected_zmp_offset_in_world: NDArray[np.float64] | None = None,
        cutoff_hz: float | None = ZMP_FILTER_HZ,
    ) -> None:
        self.alpha = (
            1.0 if cutoff_hz is None else period_s / (period_s + 1.0 / (2.0 * math.pi * cutoff_hz))
        )
        if expected_zmp_offset_in_world is None:
            expected_zmp_offset_in_world = np.zeros((1, 2))
        self._expected = np.nan_to_num(np.asarray(expected_zmp_offset_in_world, dtype=np.float64))
        self._last = self._expected.shape[0] - 1
        self._read = np.full(2, np.nan)

    def read(self, k: int, zmp_in_world: NDArray[np.float64]) -> NDArray[np.float64]:
        """The ZMP (x, y) the observer reads at period ``k`` [m], a view kept between calls.

        Real-time code: creates no numpy object (``tests/walking/test_tick_allocations.py``).
        """
        row, alpha, held = min(k, self._last), self.alpha, self._read
        expected = self._expected
        for axis in (0, 1):
            new = zmp_in_world.item(axis) - expected.item(row, axis)
            old = held.item(axis)
            if alpha >= 1.0 or not math.isfinite(new) or not math.isfinite(old):
                held[axis] = new
            else:
                held[axis] = old + alpha * (new - old)
        return held
