"""Parameters of the simulated effects, in SI units.

One frozen dataclass per effect (paper B §II, MoToFlex: motor with PID, voltage limit,
impedance, resistance and friction; gears with flexibility and tolerance; flexible links;
plus sensor errors). Angles, velocities and torques named ``*_link`` are on the joint
(output) side of the gear; those named ``*_motor`` on the rotor side. The gear ratio ``N``
maps ``q_motor = N q_link`` and ``tau_link = N tau_motor``.

Defaults are plausible values for a ~60 kg humanoid; a robot overrides them from its truth
file. How each effect is simulated is in :mod:`zmpkit.sim.builder`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from zmpkit._validate import finite, finite_array, non_negative, positive
from zmpkit.errors import ParameterError
from zmpkit.sim.spring import SofteningSpring

__all__ = [
    "FlexJoint",
    "GearParams",
    "IdealServoParams",
    "InductanceParams",
    "MotorParams",
    "SensorParams",
    "TrialVariability",
]


@dataclass(frozen=True)
class MotorParams:
    """A brushless DC motor behind a gear, driven by a PID position controller.

    The drive computes a torque command ``tau_motor = kp e + ki int(e) + kd de/dt`` on the
    motor-side error and turns it into the voltage ``v = (R/K) tau_motor + K omega_motor``
    (a current-controlled driver), clamped to ``+-voltage_limit``. The motor then gives
    ``tau_motor = K (v - K omega_motor) / R``, so at stall the torque saturates at
    ``K voltage_limit / R``.

    A *voltage drive* (``voltage_drive``: a PWM drive whose PID output is the winding voltage
    itself, with no current loop and no back-EMF compensation, as hobby and smart servos)
    gives ``v = (R/K) tau_motor`` instead: below the clamp the joint torque is
    ``k e - N² K²/R omega_link`` (the back-EMF damps the joint), at the clamp
    ``+-N K V/R - N² K²/R omega_link`` (the motor's speed-torque line), both exact. Modelling it
    as a current drive plus a rotor damping ``K²/R`` is exact only below the clamp: at the
    clamp it counts the back-EMF twice, and the joint stops producing torque at half its
    no-load speed.

    Attributes:
        torque_constant: K_t = back-EMF constant K_e in SI [N·m/A] = [V·s/rad].
        resistance: winding resistance R [Ω].
        voltage_limit: drive voltage clamp [V].
        gear_ratio: N, motor turns per link turn [-].
        rotor_inertia: rotor (+ first gear stage) inertia [kg·m²]; the link sees J N².
        coulomb_friction_link: dry friction at the joint output [N·m].
        viscous_friction_motor: viscous friction at the rotor [N·m·s/rad]; the link sees b N².
        kp_link: proportional gain, joint side [N·m/rad].
        ki_link: integral gain, joint side [N·m/(rad·s)].
        kd_link: derivative gain, joint side [N·m·s/rad].
        integral_limit_link: anti-windup clamp of the integrated joint error [rad·s]; 0 = none.
        servo_rate_hz: rate of the drive's control loop [Hz].
        voltage_drive: the PID's output is the winding voltage (a PWM drive, no back-EMF
            compensation; see above) instead of a current command.
    """

    torque_constant: float = 0.0533
    resistance: float = 1.74
    voltage_limit: float = 36.0
    gear_ratio: float = 200.0
    rotor_inertia: float = 1.8e-5
    coulomb_friction_link: float = 1.0
    viscous_friction_motor: float = 1.0e-5
    kp_link: float = 8000.0
    ki_link: float = 20000.0
    kd_link: float = 60.0
    integral_limit_link: float = 0.05
    servo_rate_hz: float = 1000.0
    voltage_drive: bool = False

    def __post_init__(self) -> None:
        for name in ("torque_constant", "resistance", "voltage_limit", "gear_ratio"):
            positive(f"MotorParams.{name}", getattr(self, name))
        for name in (
            "rotor_inertia",
            "coulomb_friction_link",
            "viscous_friction_motor",
            "kp_link",
            "ki_link",
            "kd_link",
            "integral_limit_link",
        ):
            non_negative(f"MotorParams.{name}", getattr(self, name))
        positive("MotorParams.servo_rate_hz", self.servo_rate_hz, "Hz")

    @property
    def armature_link(self) -> float:
        """Rotor inertia reflected to the joint, J N² [kg·m²]."""
        return self.rotor_inertia * self.gear_ratio**2

    @property
    def stall_torque_link(self) -> float:
        """Largest static joint torque the voltage limit allows, N K V / R [N·m]."""
        return self.gear_ratio * self.torque_constant * self.voltage_limit / self.resistance

    @property
    def back_emf_damping_link(self) -> float:
        """Joint damping of the back-EMF at a fixed voltage, N² K² / R [N·m·s/rad]."""
        return self.gear_ratio**2 * self.torque_constant**2 / self.resistance

    @property
    def no_load_speed_link(self) -> float:
        """Joint speed at which back-EMF eats the whole voltage, V / (K N) [rad/s]."""
        return self.voltage_limit / (self.torque_constant * self.gear_ratio)


@dataclass(frozen=True)
class InductanceParams:
    """Winding inductance: the current lags the voltage with the time constant L/R.

    Attributes:
        inductance: winding inductance L [H].
    """

    inductance: float = 2.0e-4

    def __post_init__(self) -> None:
        positive("InductanceParams.inductance", self.inductance, "H")

    def time_constant(self, resistance: float) -> float:
        """Electrical time constant L/R [s] for a winding resistance [Ω]."""
        return self.inductance / positive("resistance", resistance, "Ω")


@dataclass(frozen=True)
class GearParams:
    """Torsional compliance and backlash between the motor side and the link side.

    The transmitted torque is zero while the deflection ``q_link - q_motor / N`` lies inside
    the dead band ``[-backlash/2, +backlash/2]`` and ``stiffness`` times the excess outside
    it, plus ``damping`` times the deflection rate.

    Attributes:
        stiffness: torsional stiffness at the link [N·m/rad].
        damping: torsional damping at the link [N·m·s/rad].
        backlash: total dead-band width at the link [rad].
        inertia_link: inertia of the gear train on the motor side, seen at the joint
            [kg·m²]; gives the motor-side joint mass when the motor effect is off.
    """

    stiffness: float = 30000.0
    damping: float = 30.0
    backlash: float = 0.002
    inertia_link: float = 0.05

    def __post_init__(self) -> None:
        positive("GearParams.stiffness", self.stiffness, "N·m/rad")
        non_negative("GearParams.damping", self.damping, "N·m·s/rad")
        non_negative("GearParams.backlash", self.backlash, "rad")
        positive("GearParams.inertia_link", self.inertia_link, "kg·m²")


@dataclass(frozen=True)
class FlexJoint:
    """A passive compliant joint that stands for structural flexibility at one place.

    Two spring laws, plus ``-damping * x_dot``:

    - polynomial (``softening_torque = 0``): ``tau = -(k1 x + k2 x**2 + k3 x**3)`` in the
      deflection ``x`` [rad] (MuJoCo's polynomial joint spring). With ``k2 < 0 < k3`` and
      ``k2**2 < 3 k1 k3`` it softens and stiffens again, staying monotonic.
    - softening (``softening_torque > 0``): the law of
      :class:`~zmpkit.sim.spring.SofteningSpring` with ``k0 = k1``, symmetric and monotonic,
      built from native tendon springs; ``k2`` and ``k3`` must then be 0.

    Attributes:
        name: joint name in the model, e.g. ``"right_foot_pitch_flex"``.
        body: name of the body the joint is added to (the compliant part's child side).
        axis: joint axis in the body frame [-].
        anchor: joint position in the body frame [m].
        stiffness: ``(k1, k2, k3)`` in [N·m/rad], [N·m/rad²], [N·m/rad³].
        damping: viscous damping [N·m·s/rad].
        softening_torque: ``τ_s`` of the softening law [N·m]; 0 = polynomial spring.
        softening_torque_range: torque up to which the native approximation follows the
            softening law [N·m].
        softening_stages: number of linear segments of that approximation [-].
    """

    name: str
    body: str
    axis: tuple[float, float, float]
    anchor: tuple[float, float, float] = (0.0, 0.0, 0.0)
    stiffness: tuple[float, float, float] = (20000.0, 0.0, 0.0)
    damping: float = 50.0
    softening_torque: float = 0.0
    softening_torque_range: float = 50.0
    softening_stages: int = 6

    def __post_init__(self) -> None:
        k1, k2, k3 = (finite(f"FlexJoint {self.name} stiffness", k) for k in self.stiffness)
        positive(f"FlexJoint {self.name} stiffness k1", k1, "N·m/rad")
        non_negative(f"FlexJoint {self.name} stiffness k3", k3, "N·m/rad³")
        if k2 * k2 >= 3.0 * k1 * k3 and k2 != 0.0:
            raise ParameterError(
                f"FlexJoint {self.name}: stiffness (k1, k2, k3) = {self.stiffness} is not "
                "monotonic; need k2**2 < 3 k1 k3 so the spring never buckles"
            )
        non_negative(f"FlexJoint {self.name} damping", self.damping, "N·m·s/rad")
        non_negative(f"FlexJoint {self.name} softening_torque", self.softening_torque, "N·m")
        if self.softening_torque > 0.0 and (k2 != 0.0 or k3 != 0.0):
            raise ParameterError(
                f"FlexJoint {self.name}: a softening spring (softening_torque > 0) replaces "
                f"the polynomial; stiffness must be (k1, 0, 0), got {self.stiffness}"
            )
        self.spring  # noqa: B018 - validates the softening parameters

    @property
    def spring(self) -> SofteningSpring | None:
        """The softening law, or None for a polynomial spring."""
        if self.softening_torque == 0.0:
            return None
        return SofteningSpring(
            self.stiffness[0],
            self.softening_torque,
            self.softening_torque_range,
            self.softening_stages,
        )

    def torque(self, deflection: float) -> float:
        """Static spring torque the joint carries at a deflection [N·m]."""
        spring = self.spring
        if spring is not None:
            return spring.torque(deflection)
        k1, k2, k3 = self.stiffness
        return k1 * deflection + k2 * deflection**2 + k3 * deflection**3


@dataclass(frozen=True)
class IdealServoParams:
    """The stiff joint servo used when the motor effect is off ("ideal joints").

    A PID in joint space with no torque limit; the integral removes the static error.

    Attributes:
        kp: proportional gain [N·m/rad].
        ki: integral gain [N·m/(rad·s)].
        kd: derivative gain [N·m·s/rad].
    """

    kp: float = 50000.0
    ki: float = 50000.0
    kd: float = 500.0

    def __post_init__(self) -> None:
        positive("IdealServoParams.kp", self.kp)
        non_negative("IdealServoParams.ki", self.ki)
        non_negative("IdealServoParams.kd", self.kd)


@dataclass(frozen=True)
class SensorParams:
    """Errors of the robot's sensors, as a real user would meet them.

    A force–torque sample is ``quantise(lowpass(gain * w_true + offset + noise))`` taken at
    ``ft_rate_hz``, the wrench ordered ``(Fx, Fy, Fz, Tx, Ty, Tz)`` in [N] and [N·m] in the
    sensor frame. Encoders quantise the motor-side joint angle to ``encoder_resolution``.
    The IMU adds white noise to the gyro and the accelerometer.

    Attributes:
        ft_offset: per-sensor offset, shape (6,) [N, N·m]; the same for every sensor unless
            a robot gives one per sensor.
        ft_gain_error: relative gain error, so the gain is ``1 + ft_gain_error`` [-]; the
            same on every axis of every sensor (it cancels in the ZMP) unless a robot gives
            per-sensor, per-axis gains.
        ft_offset_drift_std: standard deviation of each channel's offset drift rate, drawn
            once per sensor and run from the sensor's seeded stream (temperature drift)
            [N/s, N·m/s]; zeros: none (and nothing drawn).
        ft_noise_std: white-noise standard deviation per channel, shape (6,) [N, N·m].
        ft_quantisation: output step per channel, shape (6,) [N, N·m]; 0 = none.
        ft_cutoff_hz: first-order low-pass cutoff [Hz]; 0 = no filter.
        ft_rate_hz: sample rate of the F-T sensors [Hz].
        encoder_resolution: joint-angle quantum [rad]; 0 = exact.
        gyro_noise_std: gyro white noise [rad/s].
        accel_noise_std: accelerometer white noise [m/s²].
    """

    ft_offset: tuple[float, ...] = (2.0, -1.5, 8.0, 0.3, 0.5, 0.05)
    ft_gain_error: float = 0.01
    ft_noise_std: tuple[float, ...] = (0.5, 0.5, 1.0, 0.02, 0.02, 0.01)
    ft_quantisation: tuple[float, ...] = (0.05, 0.05, 0.05, 0.002, 0.002, 0.002)
    ft_cutoff_hz: float = 30.0
    ft_rate_hz: float = 200.0
    encoder_resolution: float = 2.0e-5
    gyro_noise_std: float = 0.005
    accel_noise_std: float = 0.05
    ft_offset_drift_std: tuple[float, ...] = (0.0,) * 6

    def __post_init__(self) -> None:
        for name in ("ft_offset", "ft_noise_std", "ft_quantisation", "ft_offset_drift_std"):
            arr = finite_array(f"SensorParams.{name}", getattr(self, name), (6,))
            object.__setattr__(self, name, tuple(float(x) for x in arr))
        if any(
            np.any(np.asarray(getattr(self, name)) < 0)
            for name in ("ft_noise_std", "ft_quantisation", "ft_offset_drift_std")
        ):
            raise ParameterError(
                "SensorParams: ft_noise_std, ft_quantisation and ft_offset_drift_std must be >= 0"
            )
        finite("SensorParams.ft_gain_error", self.ft_gain_error)
        non_negative("SensorParams.ft_cutoff_hz", self.ft_cutoff_hz, "Hz")
        positive("SensorParams.ft_rate_hz", self.ft_rate_hz, "Hz")
        for name in ("encoder_resolution", "gyro_noise_std", "accel_noise_std"):
            non_negative(f"SensorParams.{name}", getattr(self, name))


@dataclass(frozen=True)
class TrialVariability:
    """What makes one trial of a virtual robot differ from the next (beyond sensor noise).

    Each is off by default, so a truth without it repeats itself exactly.

    Attributes:
        sequence: trials run in sequence without a reset, as on a real robot: before its
            trial the robot leans to the previous target of the sweep, holds it and comes
            back, so backlash and friction leave it in that lean's state (hysteresis).
        previous_hold_s: how long the previous lean is held [s].
        stance_std_rad: standard deviation of a per-trial offset of each leaning joint's
            setpoint at the start (small differences in the initial stance) [rad].
    """

    sequence: bool = False
    previous_hold_s: float = 5.0
    stance_std_rad: float = 0.0

    def __post_init__(self) -> None:
        positive("TrialVariability.previous_hold_s", self.previous_hold_s, "s")
        non_negative("TrialVariability.stance_std_rad", self.stance_std_rad, "rad")
