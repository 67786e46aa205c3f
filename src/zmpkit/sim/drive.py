"""Parameters of a joint's drive, in SI units: the motor effect (M), the winding (I), the servo.

Paper B §II, MoToFlex: a DC motor with a PID drive, voltage limit, impedance, resistance and
friction; with the motor effect off a stiff ideal servo drives the joint. Angles, velocities
and torques named ``*_link`` are on the joint (output) side of the gear; those named
``*_motor`` on the rotor side. The gear ratio ``N`` maps ``q_motor = N q_link`` and
``tau_link = N tau_motor``.

Defaults are plausible values for a ~60 kg humanoid; a robot overrides them from its truth
file. How each effect is simulated is in :mod:`zmpkit.sim.builder`.
"""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit._validate import non_negative, positive

__all__ = ["IdealServoParams", "InductanceParams", "MotorParams"]


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
