r"""The DLIPM block of paper A Fig. 19: the ankle-angle trajectory of the scheduled DLIPM.

On :meth:`DlipmController.set_target` the target is clamped to the support polygon and the
scheduled DLIPM (:class:`~zmpkit.control.schedule.GainSchedule`) is discretised exactly with
a zero-order hold of period :math:`\Delta t`:

.. math::

    \begin{bmatrix}\theta_d \\ \dot\theta_d\end{bmatrix}_{k+1}
    = A_d \begin{bmatrix}\theta_d \\ \dot\theta_d\end{bmatrix}_k + B_d\,x_{ref}, \qquad
    \theta_k = \theta_0 + \theta_{d,k}

so :math:`\theta` settles at :math:`\theta_0 + K(x_{ref})\,x_{ref} = \theta_{cmd}(x_{ref})`
(the ZOH keeps the DC gain exactly). :meth:`DlipmController.step` is real-time safe: a 2×2
update on plain floats, no array and no container allocated, then the rate and angle
limits. When a limit clamps the angle, the state is set to the clamped angle and the rate
actually realised (back-calculation), so the model never winds up beyond the output. The
state is kept across target changes, so the angle is continuous when the target changes
mid-motion.

Time scale. In SI units the DC gain fixes :math:`\beta = \gamma / K` and so
:math:`\omega_n \approx \sqrt{g/l}` (≈ 3.5 rad/s on paper A's robot): its planned
angular acceleration at a step, :math:`\beta\,\theta_{cmd}`, is far beyond what a tall
robot's servos follow.
``time_scale`` = s runs the same DLIPM s times slower (discretised with :math:`\Delta t/s`:
:math:`\omega_n/s`, same ζ, same DC gain). :data:`PAPER_A_TIME_SCALE` = √(180/π) gives
exactly the dynamics paper A ran on its robot: its code sends θ in degrees, which scales γ and β
by π/180 (its ω_n = 0.4376, see :func:`zmpkit.models.paper_units_omega_n`).

With ``max_acceleration_rad_s2`` = a, each target change picks the time scale
:math:`s = \max(s_0, \sqrt{\beta\,|\Delta\theta| / a})`: the DLIPM's step response from
rest peaks in acceleration at its start, :math:`\omega_n^2 |\Delta\theta|`, so this is the
fastest schedule of the same ζ and DC gain that the servos can follow (:math:`s_0` is
``time_scale``).
"""

from __future__ import annotations

import math

from zmpkit._validate import finite, positive
from zmpkit.control.schedule import GainSchedule
from zmpkit.errors import ParameterError
from zmpkit.models.lti import zero_order_hold

__all__ = ["PAPER_A_TIME_SCALE", "DlipmController", "support_interval"]

PAPER_A_TIME_SCALE = math.sqrt(180.0 / math.pi)
"""Time scale of paper A's implemented DLIPM (θ in degrees in its code) [-]: ≈ 7.57."""


def support_interval(name: str, value: tuple[float, float]) -> tuple[float, float]:
    """Validate ``(x_min, x_max)`` [m] with x_min < x_max."""
    try:
        low, high = (finite(f"{name}[{i}]", v) for i, v in enumerate(value))
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be (x_min, x_max) in m, got {value!r}") from None
    if not low < high:
        raise ParameterError(f"{name} must have x_min < x_max, got ({low}, {high}) m")
    return low, high


class DlipmController:
    """Gain-scheduled DLIPM ankle-angle generator for one plane (module docstring).

    Args:
        schedule: the gain surface of this plane.
        dt: control period [s].
        angle_limit_rad: the ankle angle is clamped to ±this [rad].
        rate_limit_rad_s: the ankle rate is clamped to ±this [rad/s].
        support_polygon: ``(x_min, x_max)`` of the support area in this plane [m]; targets
            are clamped into it.
        time_scale: the DLIPM trajectory runs this many times slower (module note) [-], ≥ 1
            is typical; 1 is the SI model.
        max_acceleration_rad_s2: if given, the time scale grows per target change so the
            planned angular acceleration stays within this [rad/s²] (module note).

    The controller starts at rest on target 0 (clamped into the polygon).
    """

    __slots__ = (
        "_a00",
        "_a01",
        "_a10",
        "_a11",
        "_angle",
        "_angle_max",
        "_angle_min",
        "_delta_max",
        "_requested",
        "_scale",
        "_steady",
        "_target",
        "_theta0",
        "_u0",
        "_u1",
        "_x0",
        "_x1",
        "dt",
        "max_acceleration",
        "schedule",
        "support_polygon",
        "time_scale",
    )

    def __init__(
        self,
        schedule: GainSchedule,
        dt: float,
        *,
        angle_limit_rad: float,
        rate_limit_rad_s: float,
        support_polygon: tuple[float, float],
        time_scale: float = 1.0,
        max_acceleration_rad_s2: float | None = None,
    ) -> None:
        self.schedule = schedule
        self.dt = positive("dt", dt, "s")
        self.time_scale = positive("time_scale", time_scale)
        self.max_acceleration = (
            None
            if max_acceleration_rad_s2 is None
            else positive("max_acceleration_rad_s2", max_acceleration_rad_s2, "rad/s^2")
        )
        self._angle = 0.0
        limit = positive("angle_limit_rad", angle_limit_rad, "rad")
        self._angle_min, self._angle_max = -limit, limit
        self._delta_max = positive("rate_limit_rad_s", rate_limit_rad_s, "rad/s") * self.dt
        self.support_polygon = support_interval("support_polygon", support_polygon)
        self._theta0 = schedule.theta_offset
        self.set_target(0.0)
        self.reset()

    @property
    def target(self) -> float:
        """The target in use, clamped to the support polygon [m]."""
        return self._target

    @property
    def requested_target(self) -> float:
        """The target last given to :meth:`set_target`, before clamping [m]."""
        return self._requested

    @property
    def angle(self) -> float:
        """The last ankle angle output [rad]."""
        return self._angle

    @property
    def angle_limit_rad(self) -> float:
        """The output angle is clamped to ±this [rad]."""
        return self._angle_max

    @property
    def rate(self) -> float:
        """The model's angular rate [rad/s]."""
        return self._x1

    @property
    def steady_angle(self) -> float:
        r""":math:`\theta_0 + K(x_{ref})\,x_{ref}` [rad], where the output settles."""
        return self._steady

    def set_target(self, x_ref: float) -> float:
        """Clamp ``x_ref`` [m] to the support polygon and schedule the DLIPM for it.

        Allocates (one matrix exponential); call it on target changes, not every tick.

        Returns:
            The clamped target [m].
        """
        self._requested = finite("x_ref", x_ref)
        low, high = self.support_polygon
        target = min(max(self._requested, low), high)
        system = self.schedule.dlipm(target).state_space()
        self._scale = self._time_scale_for(target)
        Ad, Bd = zero_order_hold(system.A, system.B, self.dt / self._scale)
        self._a00, self._a01 = float(Ad[0, 0]), float(Ad[0, 1])
        self._a10, self._a11 = float(Ad[1, 0]), float(Ad[1, 1])
        self._u0, self._u1 = float(Bd[0, 0]) * target, float(Bd[1, 0]) * target
        self._target = target
        self._steady = float(self.schedule.steady_angle(target))
        return target

    @property
    def active_time_scale(self) -> float:
        """The time scale in use for the current target [-]."""
        return self._scale

    def _time_scale_for(self, target: float) -> float:
        if self.max_acceleration is None:
            return self.time_scale
        swing = abs(float(self.schedule.steady_angle(target)) - self._angle)
        needed = math.sqrt(float(self.schedule.beta(target)) * swing / self.max_acceleration)
        return max(self.time_scale, needed)

    def reset(self, angle_rad: float | None = None, rate_rad_s: float = 0.0) -> None:
        """Set the state: the current ankle angle [rad] and rate [rad/s].

        Args:
            angle_rad: Current ankle angle [rad]; default: the steady angle of the current
                target, i.e. at rest there.
            rate_rad_s: Current ankle rate [rad/s].
        """
        angle = self.steady_angle if angle_rad is None else finite("angle_rad", angle_rad)
        self._angle = angle
        self._x0 = angle - self._theta0
        self._x1 = finite("rate_rad_s", rate_rad_s)

    def step(self) -> float:
        """Advance one period and return the ankle angle [rad] to command.

        Real-time safe: float arithmetic only; clamps rate, then angle.
        """
        x0, x1, previous = self._x0, self._x1, self._angle
        theta_d = self._a00 * x0 + self._a01 * x1 + self._u0
        rate = self._a10 * x0 + self._a11 * x1 + self._u1
        angle = free = self._theta0 + theta_d
        if angle > previous + self._delta_max:
            angle = previous + self._delta_max
        elif angle < previous - self._delta_max:
            angle = previous - self._delta_max
        if angle > self._angle_max:
            angle = self._angle_max
        elif angle < self._angle_min:
            angle = self._angle_min
        if angle != free:  # a limit acted: back-calculate the state
            theta_d = angle - self._theta0
            rate = (angle - previous) / self.dt
        self._x0, self._x1, self._angle = theta_d, rate, angle
        return angle

    def __repr__(self) -> str:
        return (
            f"DlipmController(target={self._target:.6g} m, angle={self._angle:.6g} rad, "
            f"dt={self.dt} s, theta_offset={self._theta0:.6g} rad)"
        )
