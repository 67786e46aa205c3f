r"""The joint servo's trajectory interpolation: velocity- and acceleration-limited setpoints.

A position drive does not jump to a new target: it moves its setpoint there along a
trapezoidal velocity profile (e.g. paper A's drives in profile-position mode). Each tick every
joint's setpoint velocity moves toward

.. math::
    v_{des} = \operatorname{sign}(e) \min(v_{max}, \sqrt{2 a_{max} |e|}),

the fastest speed from which it can still stop at the target, changing by at most
``a_max dt`` per tick. A commanded step thus passes through the joint's own limits, as on
the real robot — a raw angle step on a 0.9 m, 62 kg pendulum would tip it over.

With ``synchronized`` limits (paper A's robot: its host interpolates all joints of a part together
in cyclic synchronous position mode) each new target scales joint ``i``'s limits
by ``|e_i| / max_j |e_j|``, its share of the largest remaining move, so joints that start
at rest move in proportion and arrive together. This matters in closed chains: the two
legs of a robot in double support must stay kinematically compatible on the way, or stiff
servos fight each other through the floor. A joint that is still moving keeps at least
the limits it had, so it can always stop.

Plain Python floats: on 14 joints they beat numpy by about 4×, and a tick allocates nothing
beyond the float results.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from zmpkit._validate import positive
from zmpkit.errors import ParameterError

__all__ = ["ServoLimits", "TrajectoryLimiter"]

_ARRIVED_RAD = 1e-12


@dataclass(frozen=True)
class ServoLimits:
    """Limits of the setpoint trajectory, the same for every joint.

    Attributes:
        max_velocity: joint speed limit [rad/s].
        max_acceleration: joint acceleration limit [rad/s²].
        synchronized: scale each joint's limits by its share of the largest move, so the
            joints of one command move in proportion and arrive together.
    """

    max_velocity: float = 0.35
    max_acceleration: float = 1.0
    synchronized: bool = False

    def __post_init__(self) -> None:
        positive("ServoLimits.max_velocity", self.max_velocity, "rad/s")
        positive("ServoLimits.max_acceleration", self.max_acceleration, "rad/s²")


class TrajectoryLimiter:
    """Moves per-joint setpoints toward their targets within velocity and acceleration limits.

    Args:
        initial: starting setpoints [rad], one per joint.
        limits: velocity and acceleration limits.
        dt: tick period [s].
    """

    def __init__(self, initial: Sequence[float], limits: ServoLimits, dt: float) -> None:
        self._dt = positive("dt", dt, "s")
        self._vmax = limits.max_velocity
        self._amax = limits.max_acceleration
        self._synchronized = limits.synchronized
        self.position: list[float] = [float(q) for q in initial]
        self.velocity: list[float] = [0.0] * len(self.position)
        self.target: list[float] = list(self.position)
        self._scale: list[float] = [1.0] * len(self.position)
        self._moving = False

    @property
    def moving(self) -> bool:
        """Whether any setpoint is still on its way to its target."""
        return self._moving

    def set_target(self, target: Sequence[float]) -> None:
        """Give new targets [rad], one per joint."""
        if len(target) != len(self.position):
            raise ParameterError(
                f"target must have {len(self.position)} joint angles, got {len(target)}"
            )
        self.target = [float(q) for q in target]
        if self._synchronized:
            moves = [abs(g - q) for g, q in zip(self.target, self.position, strict=True)]
            largest = max(moves)
            self._scale = [
                1.0 if largest == 0.0 else max(m / largest, s if v != 0.0 else 0.0)
                for m, s, v in zip(moves, self._scale, self.velocity, strict=True)
            ]
        self._moving = True

    def reset(self, position: Sequence[float]) -> None:
        """Jump to ``position`` [rad] at rest, targets included."""
        self.position = [float(q) for q in position]
        self.velocity = [0.0] * len(self.position)
        self.target = list(self.position)
        self._scale = [1.0] * len(self.position)
        self._moving = False

    def tick(self) -> list[float]:
        """Advance one period and return the setpoints [rad]."""
        if not self._moving:
            return self.position
        dt = self._dt
        moving = False
        for i, (q, v, goal, scale) in enumerate(
            zip(self.position, self.velocity, self.target, self._scale, strict=True)
        ):
            err = goal - q
            amax = self._amax * scale
            dv = amax * dt
            if abs(err) < _ARRIVED_RAD and abs(v) <= dv:
                self.position[i], self.velocity[i] = goal, 0.0
                continue
            v_des = math.copysign(min(self._vmax * scale, math.sqrt(2.0 * amax * abs(err))), err)
            v_new = min(max(v_des, v - dv), v + dv)
            q_new = q + v_new * dt
            if (goal - q_new) * err <= 0.0 and abs(v_new) <= dv:
                q_new, v_new = goal, 0.0
            else:
                moving = True
            self.position[i], self.velocity[i] = q_new, v_new
        self._moving = moving
        return self.position
