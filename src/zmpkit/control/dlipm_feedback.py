r"""A lean feedforward plus a clamped PI on the measured ZMP's mismatch with its model.

The DLIPM (:class:`~zmpkit.control.DlipmController`) plans the ankle angle from the identified
model; whatever the model misses (trial-to-trial variability, creep, a schedule fitted on
other data) is left as a steady-state ZMP error. A PI on the measured ZMP removes it. Its
error is not the target minus the measurement but the **model's mismatch**: the ZMP the
identified model expects at the feedforward's current angle, minus the measured ZMP,

.. math::

    x_{exp,k} = f(l\sin\theta_{ff,k}), \qquad
    \hat e_k = \hat e_{k-1} + a\,\big((x_{exp,k} - x_{meas,k}) - \hat e_{k-1}\big), \quad
    a = 1 - e^{-\Delta t/\tau_f},

    I_{k+1} = \operatorname{clamp}(I_k + K_i\,\hat e_k\,\Delta t,\ \pm I_{max}), \qquad
    \Delta\theta_k = \operatorname{clamp}(K_p \hat e_k + I_{k+1},\ \pm\Delta\theta_{max}),

    \theta_k = \operatorname{clamp}(\theta_{ff,k} + \Delta\theta_k,\ \pm\theta_{max}).

At the feedforward's steady angle :math:`x_{exp} = x_{ref}` (the schedule inverts f), so the
loop removes the same steady-state error as a PI on :math:`x_{ref} - x_{meas}`; during the
planned lean, though, the error is only what the model gets wrong, so the integral does not
wind up on the lean itself (with :math:`x_{ref} - x_{meas}` it did: the DLIPM's 0.10 m step
overshot to 0.13 m). The static model lags the moving robot all the same (the measured ZMP
holds the acceleration and the flex), so the PI acts only once the plan is still: while the
feedforward is farther than ``still_angle_rad`` (:data:`STILL_ANGLE_RAD`) from its steady
angle the filter restarts and the integral and the correction hold (integrating the lag left
+0.2 to +0.5 % on every target, decaying at the integral's slow rate). The LIPM's model is
:math:`f(u) = u`: wrapped around the LIPM (:class:`~zmpkit.control.LipmController`, open
loop) the same PI makes LIPM+PID.

The mismatch is low-passed (time constant :math:`\tau_f`; the filter starts at the first
sample): the ZMP holds the pendulum's acceleration term, :math:`p = x - (z_c/g)\,\ddot x`,
whose gain from the lean grows as :math:`\omega^2/\omega_0^2` and peaks at the robot's
under-damped flex modes (1–2 Hz); unfiltered, even a small proportional gain closes a loop
around them.

Anti-windup by **conditional integration**: the integral keeps its value on a tick where the
output (the correction or the summed angle) is clamped and the error would push it further
into that limit; it is also clamped to ``±integral_limit_rad`` on its own. A missing sample
(``step(None)``: a dropout, or a sample the plausibility gate rejected) holds the integral
and the last correction; the feedforward keeps running.

Gain rule (:meth:`ZmpFeedbackGains.from_plant`), not tuned per target: near steady state
the plant from a lean correction to the measured ZMP is its DC gain
:math:`G_0 = \partial x_{meas} / \partial\theta = l\,f'(0)` [m/rad] (lean length times the
identified slope of the error model). The integral's crossover is put twenty times below the
pendulum's natural frequency :math:`\omega_0 = \sqrt{g/l}`, far from the under-damped mode
it must not excite, :math:`K_i = \omega_0 / (20\,G_0)`; the proportional loop gain is
:math:`K_p G_0 = 0.02`; the filter's corner is at :math:`\omega_0/2`
(:math:`\tau_f = 2/\omega_0`), ten times the integral's crossover. Measured on the virtual
balance robot's frontal plane at 0.10 m (25 s holds): a loop gain :math:`K_p G_0` of 0.1
grew a 1.4 Hz oscillation of 60 mm peak to peak after 10 s, 0.05 did not, so 0.02 keeps a
margin of five; with a schedule 25 % off, a crossover of ω₀/10 overshot 18 % and ω₀/20 6 %
(both removed the offset).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit._validate import non_negative, positive
from zmpkit.control.dlipm_controller import DlipmController
from zmpkit.control.lipm_controller import LipmController
from zmpkit.errors import ParameterError
from zmpkit.identify.error_model import ErrorModel
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2

__all__ = [
    "FILTER_CORNER_FRACTION",
    "INTEGRAL_CROSSOVER_FRACTION",
    "PROPORTIONAL_LOOP_GAIN",
    "STILL_ANGLE_RAD",
    "DlipmFeedbackController",
    "ZmpFeedbackGains",
]

INTEGRAL_CROSSOVER_FRACTION = 0.05
"""The integral's crossover frequency as a fraction of the pendulum's √(g/l) [-]."""
PROPORTIONAL_LOOP_GAIN = 0.02
"""The proportional part's loop gain K_p G_0 [-]."""
STILL_ANGLE_RAD = 0.002
"""The PI acts only while the feedforward is within this of its steady angle [rad]."""
FILTER_CORNER_FRACTION = 0.5
"""The measurement filter's corner frequency as a fraction of √(g/l) [-]."""


@dataclass(frozen=True)
class ZmpFeedbackGains:
    """PI gains on the ZMP error; the output is an ankle-angle correction.

    Attributes:
        kp_rad_per_m: proportional gain [rad/m].
        ki_rad_per_m_s: integral gain [rad/(m·s)].
        integral_limit_rad: the integral is clamped to ±this [rad].
        output_limit_rad: the correction is clamped to ±this [rad].
        filter_time_constant_s: low-pass of the measured ZMP, τ_f [s]; 0: none.
        still_angle_rad: the PI acts only while the feedforward is within this of its
            steady angle [rad]; inf: always.
    """

    kp_rad_per_m: float
    ki_rad_per_m_s: float
    integral_limit_rad: float
    output_limit_rad: float
    filter_time_constant_s: float = 0.0
    still_angle_rad: float = math.inf

    def __post_init__(self) -> None:
        non_negative("kp_rad_per_m", self.kp_rad_per_m, "rad/m")
        non_negative("ki_rad_per_m_s", self.ki_rad_per_m_s, "rad/(m·s)")
        positive("integral_limit_rad", self.integral_limit_rad, "rad")
        positive("output_limit_rad", self.output_limit_rad, "rad")
        non_negative("filter_time_constant_s", self.filter_time_constant_s, "s")
        if self.still_angle_rad != math.inf:
            positive("still_angle_rad", self.still_angle_rad, "rad")

    @classmethod
    def from_plant(
        cls,
        dc_gain_m_per_rad: float,
        lean_length_m: float,
        output_limit_rad: float,
        g: float = STANDARD_GRAVITY_MPS2,
    ) -> ZmpFeedbackGains:
        r"""The documented gain rule (module docstring) for a plant of DC gain :math:`G_0`.

        Args:
            dc_gain_m_per_rad: :math:`G_0 = \partial x_{meas}/\partial\theta` [m/rad], > 0.
            lean_length_m: pendulum length l, ankle to CoM [m].
            output_limit_rad: the correction's clamp, also the integral's [rad].
            g: gravitational acceleration [m/s²].
        """
        g0 = positive("dc_gain_m_per_rad", dc_gain_m_per_rad, "m/rad")
        omega0 = math.sqrt(positive("g", g, "m/s^2") / positive("lean_length_m", lean_length_m))
        return cls(
            kp_rad_per_m=PROPORTIONAL_LOOP_GAIN / g0,
            ki_rad_per_m_s=INTEGRAL_CROSSOVER_FRACTION * omega0 / g0,
            integral_limit_rad=output_limit_rad,
            output_limit_rad=output_limit_rad,
            filter_time_constant_s=1.0 / (FILTER_CORNER_FRACTION * omega0),
            still_angle_rad=STILL_ANGLE_RAD,
        )


class DlipmFeedbackController:
    """Scheduled DLIPM feedforward plus a clamped, conditionally integrating PI (module doc).

    Args:
        feedforward: the scheduled DLIPM of this plane (its limits bound the feedforward).
        gains: the PI's gains and clamps.

    The measured ZMP given to :meth:`step` must have the start-up offset removed, as the
    target is relative to the robot's standing ZMP.
    """

    __slots__ = (
        "_alpha",
        "_angle",
        "_correction",
        "_dabc",
        "_filtered",
        "_integral",
        "_length",
        "_limit",
        "_odd",
        "_still_angle_rad",
        "feedforward",
        "gains",
    )

    reads_zmp = True
    """It wants the measured ZMP each tick (:meth:`step`)."""

    def __init__(
        self, feedforward: DlipmController | LipmController, gains: ZmpFeedbackGains
    ) -> None:
        if isinstance(feedforward, LipmController) and feedforward.pid is not None:
            raise ParameterError("the LIPM feedforward must be open loop (pid=None)")
        self.feedforward = feedforward
        self.gains = gains
        if isinstance(feedforward, DlipmController):
            self._limit = feedforward.angle_limit_rad
            model = feedforward.schedule.error_model
            self._length = feedforward.schedule.length
        else:  # the LIPM's own model: the ZMP is l sin θ
            self._limit = feedforward.angle_limit
            model = ErrorModel("linear", (1.0, 0.0))
            self._length = feedforward.length
        d, a, b, c = (model.coefficient(name) for name in ("d", "a", "b", "c"))
        self._dabc = (d, a, b, c)
        self._odd = model.kind == "odd_quadratic"
        tau = gains.filter_time_constant_s
        self._alpha = 1.0 if tau == 0.0 else -math.expm1(-feedforward.dt / tau)
        self._still_angle_rad = gains.still_angle_rad
        self._integral = self._correction = 0.0
        self._filtered = math.nan  # no sample yet
        self._angle = feedforward.angle

    @property
    def target(self) -> float:
        """The target in use, clamped to the support polygon [m]."""
        return self.feedforward.target

    @property
    def angle(self) -> float:
        """The last ankle angle output [rad]."""
        return self._angle

    @property
    def integral(self) -> float:
        """The PI's integral state [rad]."""
        return self._integral

    @property
    def correction(self) -> float:
        """The last feedback correction added to the feedforward [rad]."""
        return self._correction

    def set_target(self, x_ref: float) -> float:
        """Set the ZMP target [m] (clamped to the support polygon); the PI state is kept."""
        return self.feedforward.set_target(x_ref)

    def reset(self, angle_rad: float | None = None) -> None:
        """Reset the feedforward to ``angle_rad`` [rad] (default: at rest) and clear the PI."""
        self.feedforward.reset(angle_rad)
        self._integral = self._correction = 0.0
        self._filtered = math.nan
        self._angle = self.feedforward.angle

    def step(self, measured_zmp_m: float | None = None) -> float:
        """Advance one period; the ankle angle to command [rad].

        Args:
            measured_zmp_m: this tick's measured ZMP, offset removed [m]; None: a missing
                sample, the integral and the correction are held.
        """
        feedforward = self.feedforward.step()
        if abs(feedforward - self.feedforward.steady_angle) > self._still_angle_rad:
            self._filtered = math.nan  # the plan is moving: the PI holds (module docstring)
        elif measured_zmp_m is not None:
            mismatch = self.expected_zmp(feedforward) - measured_zmp_m
            self._update(self._filter(mismatch), feedforward)
        angle = feedforward + self._correction
        limit = self._limit
        self._angle = limit if angle > limit else -limit if angle < -limit else angle
        return self._angle

    def expected_zmp(self, feedforward_angle_rad: float) -> float:
        r"""The ZMP the identified model expects at a feedforward angle [rad] → [m].

        :math:`x_{exp} = f(l\sin\theta_{ff})`: at the DLIPM's steady angle this is the target.
        """
        d, a, b, c = self._dabc
        u = self._length * math.sin(feedforward_angle_rad)
        square = u * abs(u) if self._odd else u * u
        return d * u * u * u + a * square + b * u + c

    def _filter(self, mismatch_m: float) -> float:
        """The low-passed model mismatch [m]; the filter starts at the first sample."""
        previous = self._filtered
        if previous != previous:  # NaN: first sample
            self._filtered = mismatch_m
        else:
            self._filtered = previous + self._alpha * (mismatch_m - previous)
        return self._filtered

    def _update(self, error_m: float, feedforward: float) -> None:
        """The PI with conditional integration; sets the correction [rad]."""
        gains = self.gains
        if not math.isfinite(error_m):
            raise ParameterError(f"measured_zmp_m must be finite or None, got error {error_m}")
        limit, ilimit = gains.output_limit_rad, gains.integral_limit_rad
        proportional = gains.kp_rad_per_m * error_m
        integral = self._integral + gains.ki_rad_per_m_s * error_m * self.feedforward.dt
        integral = ilimit if integral > ilimit else -ilimit if integral < -ilimit else integral
        total = proportional + integral
        pushes_up = error_m > 0.0 and (total > limit or feedforward + total > self._limit)
        pushes_down = error_m < 0.0 and (total < -limit or feedforward + total < -self._limit)
        if pushes_up or pushes_down:
            total = proportional + self._integral  # saturated: the integral stays
        else:
            self._integral = integral
        self._correction = limit if total > limit else -limit if total < -limit else total

    def __repr__(self) -> str:
        return (
            f"DlipmFeedbackController(target={self.target:.6g} m, angle={self._angle:.6g} rad, "
            f"integral={self._integral:.6g} rad)"
        )
