"""What disturbs a simulated walk: pushes on the torso and faults of the robot's sensors.

Pushes (:class:`Push`) are external forces on the torso, applied at its CoM in the world
frame (:class:`TorsoPusher`, physics step by physics step). Sensor faults
(:class:`SensorFault`) corrupt what the walking controller reads, never what is recorded.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.sim.world import Simulation
from zmpkit.walking.measurement import WalkMeasurement

__all__ = ["FAULTS", "PUSH_DIRECTIONS", "Push", "SensorFault", "TorsoPusher"]


_DIAGONAL = 0.5**0.5


PUSH_DIRECTIONS: dict[str, tuple[float, float]] = {
    "x": (1.0, 0.0), "-x": (-1.0, 0.0), "y": (0.0, 1.0), "-y": (0.0, -1.0),
    "x+y": (_DIAGONAL, _DIAGONAL), "x-y": (_DIAGONAL, -_DIAGONAL),
    "-x+y": (-_DIAGONAL, _DIAGONAL), "-x-y": (-_DIAGONAL, -_DIAGONAL),
}  # fmt: skip
"""Push directions in the world frame (x forward, y left), unit vectors: the axes and the
diagonals between them."""


@dataclass(frozen=True)
class Push:
    """A horizontal force on the torso for a while (the usual push-recovery test).

    Attributes:
        force_n: magnitude [N], > 0.
        time_s: when it starts [s].
        direction: one of :data:`PUSH_DIRECTIONS`.
        duration_s: how long it lasts [s].
    """

    force_n: float
    time_s: float
    direction: str = "x"
    duration_s: float = 0.1

    def __post_init__(self) -> None:
        _validate.positive("Push.force_n", self.force_n, "N")
        _validate.non_negative("Push.time_s", self.time_s, "s")
        _validate.positive("Push.duration_s", self.duration_s, "s")
        if self.direction not in PUSH_DIRECTIONS:
            raise ParameterError(
                f"Push.direction must be one of {', '.join(PUSH_DIRECTIONS)}; "
                f"got {self.direction!r}"
            )

    @classmethod
    def parse(cls, text: str) -> Push:
        """Read ``FORCE_N@TIME_S[:DIR]``, e.g. ``20@3.5:y`` (direction x when not given)."""
        force, _, rest = text.partition("@")
        when, _, direction = rest.partition(":")
        try:
            return cls(float(force), float(when), direction or "x")
        except ValueError:
            raise ParameterError(
                f"a push is FORCE_N@TIME_S[:DIR] with DIR one of {', '.join(PUSH_DIRECTIONS)}, "
                f"e.g. 20@3.5:y; got {text!r}"
            ) from None

    def force_in_world(self, time_s: float) -> tuple[float, float]:
        """The force at ``time_s`` [N] (x, y); zero outside the push."""
        if not self.time_s <= time_s < self.time_s + self.duration_s:
            return 0.0, 0.0
        ux, uy = PUSH_DIRECTIONS[self.direction]
        return self.force_n * ux, self.force_n * uy


class TorsoPusher:
    """Applies the pushes to the torso, physics step by physics step."""

    def __init__(self, sim: Simulation, pushes: Sequence[Push]) -> None:
        self.sim, self.pushes = sim, tuple(pushes)
        self.body = 1  # the floating base (torso)

    def apply(self) -> None:
        """Set the torso's external force [N] (world x, y) for the current time."""
        if not self.pushes:
            return
        t = self.sim.time
        fx = fy = 0.0
        for push in self.pushes:
            px, py = push.force_in_world(t)
            fx, fy = fx + px, fy + py
        self.sim.data.xfrc_applied[self.body, 0] = fx
        self.sim.data.xfrc_applied[self.body, 1] = fy


FAULTS: dict[str, str] = {
    "ft_dropout": "both F-T sensors read zero for 50 ms",
    "ft_spike": "one sample of +500 N on the right foot's F_z",
    "ft_nan": "both F-T sensors read NaN for 30 ms",
    "gyro_bias": "a 0.05 rad/s gyro bias about z: the IMU's yaw drifts from the start",
}
"""Sensor faults a controller meets, by name."""


@dataclass(frozen=True)
class SensorFault:
    """A fault of the robot's sensors, as the controller reads them (:data:`FAULTS`).

    Attributes:
        kind: one of :data:`FAULTS`.
        time_s: when it starts [s] (a bias is there from the start).
    """

    kind: str
    time_s: float = 0.0

    DROPOUT_S = 0.05
    NAN_S = 0.03
    SPIKE_N = 500.0
    GYRO_BIAS_RPS = 0.05

    def __post_init__(self) -> None:
        if self.kind not in FAULTS:
            raise ParameterError(f"a sensor fault is one of {', '.join(FAULTS)}; got {self.kind!r}")
        _validate.non_negative("SensorFault.time_s", self.time_s, "s")

    def apply(self, measurement: WalkMeasurement, frame_s: float) -> None:
        """Corrupt ``measurement`` (read at ``measurement.time_s``) in place."""
        t, start = measurement.time_s, self.time_s
        if self.kind == "gyro_bias":
            yaw = self.GYRO_BIAS_RPS * t
            measurement.gyro_rps[2] += self.GYRO_BIAS_RPS
            drift = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
            q = measurement.imu_quaternion.copy()
            measurement.imu_quaternion[0] = drift[0] * q[0] - drift[3] * q[3]
            measurement.imu_quaternion[1] = drift[0] * q[1] - drift[3] * q[2]
            measurement.imu_quaternion[2] = drift[0] * q[2] + drift[3] * q[1]
            measurement.imu_quaternion[3] = drift[0] * q[3] + drift[3] * q[0]
        elif self.kind == "ft_dropout" and start <= t < start + self.DROPOUT_S:
            measurement.force_in_sensor[:] = 0.0
            measurement.moment_in_sensor[:] = 0.0
        elif self.kind == "ft_nan" and start <= t < start + self.NAN_S:
            measurement.force_in_sensor[:] = np.nan
            measurement.moment_in_sensor[:] = np.nan
        elif self.kind == "ft_spike" and start <= t < start + frame_s:
            right = measurement.feet.index("right") if "right" in measurement.feet else 0
            measurement.force_in_sensor[right, 2] += self.SPIKE_N
