r"""A swing sole kept level in the world: the trunk's measured pitch taken off it.

The whole-body IK places the swing sole parallel to the ground of a robot that stands as
planned. A push that pitches the robot over its stance sole pitches the swing sole with
it, and its toe meets the ground before its centre does. Measured on the built-in walker
(``zmpip``, all effects, step adjustment on, 20 N along x at a quarter of the seventh
step): the trunk pitched 0.157 rad forward by 72 % of the swing after the push; the swing
sole's centre was then 1.2 cm above the ground, its toe (half a sole length, 8 cm, ahead
of it) at the ground, and the contact ended the swing 0.1 s early and 2.7 cm short of its
goal. With the pitch taken off the sole, it landed flat at 85 % of the swing, 3 mm from its
goal.

Every control tick the trunk's pitch change since the walk's first tick,
``Δθ = θ_{IMU} - θ_{IMU,0}`` (ZYX Euler pitch, nose down positive), is taken off every
foot in the air (its target above the ground):

.. math:: θ_{foot} = -Δθ \quad (z_{foot} > 0), \qquad θ_{foot} = 0 \quad \text{otherwise}.

Pitch only: taking the roll off as well (either sign) made 9 of the 16 tuning pushes
fall, against 5 with the pitch alone (:mod:`zmpkit.walking.step_adjustment_parameters`).
A tick reads the IMU's quaternion and writes floats; it allocates nothing.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from zmpkit.sensors.imu import quaternion_pitch_roll

__all__ = ["IN_AIR_M", "LevelSwing"]

IN_AIR_M = 1e-4
"""A foot whose target is higher than this above the ground is in the air [m]."""


class LevelSwing:
    """The swing soles' pitch that cancels the trunk's (module docstring).

    Args:
        enabled: False keeps every sole parallel to the planned ground (pitch 0).

    Attributes:
        trunk_pitch_change_rad: Δθ of the last :meth:`update` [rad].
    """

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled
        self._start_rad: float | None = None
        self.trunk_pitch_change_rad = 0.0

    def update(self, imu_quaternion_wxyz: NDArray[np.float64]) -> None:
        """Read the trunk's pitch from the IMU's orientation (w, x, y, z) [-]."""
        pitch, _ = quaternion_pitch_roll(imu_quaternion_wxyz)
        if self._start_rad is None:
            self._start_rad = pitch
        self.trunk_pitch_change_rad = pitch - self._start_rad

    def foot_pitch_rad(self, foot_height_m: float) -> float:
        """The pitch [rad] of a sole whose target is ``foot_height_m`` [m] above the ground."""
        if not self.enabled or foot_height_m <= IN_AIR_M:
            return 0.0
        return -self.trunk_pitch_change_rad
