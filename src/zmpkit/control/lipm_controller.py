r"""The classic LIPM baseline of paper A Fig. 9, and a single linear correction of it.

:class:`LipmController` commands the static pendulum angle of the target,

.. math:: \theta = \arcsin(x_{cmd} / l) + \Delta\theta_{PID}, \qquad x_{cmd} = x_{ref}

optionally corrected by a PID on the measured ZMP (:class:`PidGains`),

.. math::

    e = x_{ref} - x_{meas}, \qquad
    \Delta\theta_{PID} = K_p e + K_i \textstyle\int e\,dt - K_d\,\dot x_{meas}

(derivative on the measurement, so a target step gives no kick), clamped to
``±output_limit_rad``, with conditional integration as anti-windup: the integral does not
grow while the output is clamped in the direction of the error.

:class:`LinearCorrectionController` is the same with :math:`x_{cmd} = (x_{ref} - c)/b`: the
fitted slope and offset of the error model at :math:`x_{cmd} = 0`, one constant correction,
to show what the gain schedule adds over it.

Both share the interface of :class:`~zmpkit.control.DlipmController`: ``set_target(x_ref)``
(clamped to the support polygon) and a real-time-safe ``step(measured_zmp=None)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from zmpkit._validate import finite, non_negative, positive
from zmpkit.control.dlipm_controller import support_interval
from zmpkit.errors import ParameterError
from zmpkit.identify.error_model import ErrorModel

__all__ = ["LinearCorrectionController", "LipmController", "PidGains"]


@dataclass(frozen=True)
class PidGains:
    """PID on the ZMP error, output an ankle-angle correction.

    Attributes:
        kp_rad_per_m: proportional gain [rad/m].
        ki_rad_per_m_s: integral gain [rad/(m·s)].
        kd_rad_s_per_m: derivative gain [rad·s/m].
        output_limit_rad: the correction is clamped to ±this [rad].
    """

    kp_rad_per_m: float
    ki_rad_per_m_s: float = 0.0
    kd_rad_s_per_m: float = 0.0
    output_limit_rad: float = 0.05

    def __post_init__(self) -> None:
        for name in ("kp_rad_per_m", "ki_rad_per_m_s", "kd_rad_s_per_m"):
            object.__setattr__(self, name, non_negative(name, getattr(self, name)))
        limit = positive("output_limit_rad", self.output_limit_rad, "rad")
        object.__setattr__(self, "output_limit_rad", limit)


class LipmController:
    """Static-pendulum ankle angle of the target, optionally PID-corrected (module docstring).

    Args:
        length: pendulum length, ankle to CoM [m].
        dt: control period [s].
        angle_limit_rad: the ankle angle is clamped to ±this [rad].
        rate_limit_rad_s: the ankle rate is clamped to ±this [rad/s]; None: no limit (the
            classic experiment steps the angle).
        support_polygon: ``(x_min, x_max)`` of the support area in this plane [m].
        pid: PID gains on the measured ZMP; None: open loop.
    """

    __slots__ = (
        "_angle",
        "_delta_max",
        "_feedforward",
        "_integral",
        "_previous_zmp",
        "_requested",
        "_target",
        "angle_limit",
        "dt",
        "length",
        "pid",
        "support_polygon",
    )

    def __init__(
        self,
        length: float,
        dt: float,
        *,
        angle_limit_rad: float,
        rate_limit_rad_s: float | None = None,
        support_polygon: tuple[float, float],
        pid: PidGains | None = None,
    ) -> None:
        self.length = positive("length", length, "m")
        self.dt = positive("dt", dt, "s")
        self.angle_limit = positive("angle_limit_rad", angle_limit_rad, "rad")
        self._delta_max = (
            math.inf
            if rate_limit_rad_s is None
            else positive("rate_limit_rad_s", rate_limit_rad_s, "rad/s") * self.dt
        )
        self.support_polygon = support_interval("support_polygon", support_polygon)
        self.pid = pid
        self._integral, self._previous_zmp = 0.0, math.nan
        self.set_target(0.0)
        self._angle = self._feedforward

    @property
    def target(self) -> float:
        """The target in use, clamped to the support polygon [m]."""
        return self._target

    @property
    def angle(self) -> float:
        """The last ankle angle output [rad]."""
        return self._angle

    @property
    def steady_angle(self) -> float:
        """The feed-forward angle of the target, where the open-loop output settles [rad]."""
        return self._feedforward

    @property
    def reads_zmp(self) -> bool:
        """Whether :meth:`step` wants the measured ZMP (it has a PID)."""
        return self.pid is not None

    def commanded_zmp(self, x_ref: float) -> float:
        """The LIPM-expected ZMP to command for target ``x_ref`` [m]: the target itself."""
        return x_ref

    def set_target(self, x_ref: float) -> float:
        """Clamp ``x_ref`` [m] to the support polygon; the feed-forward is asin(x_cmd/l).

        Raises:
            ParameterError: if the commanded ZMP is not inside the pendulum, |x_cmd| < l.
        """
        self._requested = finite("x_ref", x_ref)
        low, high = self.support_polygon
        target = min(max(self._requested, low), high)
        x_cmd = self.commanded_zmp(target)
        if not abs(x_cmd) < self.length:
            raise ParameterError(
                f"x_ref = {target} m needs the commanded ZMP {x_cmd} m, which must satisfy "
                f"|x_cmd| < l = {self.length} m for asin(x_cmd/l) to exist"
            )
        self._target, self._feedforward = target, math.asin(x_cmd / self.length)
        return target

    def reset(self, angle_rad: float | None = None) -> None:
        """Clear the PID state and set the last output angle [rad] (default: feed-forward)."""
        self._integral, self._previous_zmp = 0.0, math.nan
        self._angle = self._feedforward if angle_rad is None else finite("angle_rad", angle_rad)

    def step(self, measured_zmp: float | None = None) -> float:
        """Advance one period; return the ankle angle [rad].

        Args:
            measured_zmp: this tick's measured ZMP [m]; None (e.g. no foot in contact) skips
                the P and D terms and holds the integral.
        """
        angle = self._feedforward + self._correction(measured_zmp)
        previous = self._angle
        if angle > previous + self._delta_max:
            angle = previous + self._delta_max
        elif angle < previous - self._delta_max:
            angle = previous - self._delta_max
        if angle > self.angle_limit:
            angle = self.angle_limit
        elif angle < -self.angle_limit:
            angle = -self.angle_limit
        self._angle = angle
        return angle

    def _correction(self, measured_zmp: float | None) -> float:
        """The clamped PID correction [rad], with conditional integration."""
        pid = self.pid
        if pid is None:
            return 0.0
        limit = pid.output_limit_rad
        if measured_zmp is None:
            return min(max(self._integral, -limit), limit)
        error = self._target - measured_zmp
        slope = (
            0.0 if self._previous_zmp != self._previous_zmp else measured_zmp - self._previous_zmp
        )
        self._previous_zmp = measured_zmp
        partial = pid.kp_rad_per_m * error - pid.kd_rad_s_per_m * slope / self.dt
        integral = self._integral + pid.ki_rad_per_m_s * error * self.dt
        total = partial + integral
        if (total > limit and error > 0.0) or (total < -limit and error < 0.0):
            total = partial + self._integral  # windup: keep the integral where it was
        else:
            self._integral = integral
        return min(max(total, -limit), limit)


class LinearCorrectionController(LipmController):
    """The LIPM baseline with one constant correction, x_cmd = (x_ref − c)/b.

    Args:
        length: pendulum length [m].
        dt: control period [s].
        slope: b, the fitted d x_measured / d x_cmd at x_cmd = 0 [-], > 0.
        offset: c, the fitted measured ZMP at x_cmd = 0 [m].
        **kwargs: as :class:`LipmController` (limits, support polygon, PID).
    """

    __slots__ = ("offset", "slope")

    def __init__(
        self, length: float, dt: float, *, slope: float, offset: float, **kwargs: Any
    ) -> None:
        self.slope = positive("slope", slope)
        self.offset = finite("offset", offset)
        super().__init__(length, dt, **kwargs)

    @classmethod
    def from_error_model(
        cls, error_model: ErrorModel, length: float, dt: float, **kwargs: Any
    ) -> LinearCorrectionController:
        """Build the controller with b = f'(0) and c = f(0) of an identified error model.

        These are the error model's b and c coefficients.
        """
        slope = float(error_model.derivative(0.0))
        return cls(length, dt, slope=slope, offset=float(error_model.predict(0.0)), **kwargs)

    def commanded_zmp(self, x_ref: float) -> float:
        """(x_ref − c)/b [m]."""
        return (x_ref - self.offset) / self.slope
