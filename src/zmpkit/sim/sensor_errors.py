"""Parameters of the sensor errors (effect S) and of the trial-to-trial differences, in SI units.

What a real user meets in a robot's readings: F-T offsets, gain errors, noise, filtering and
quantisation, encoder resolution and IMU noise; and what makes one trial of a virtual robot
differ from the next. Defaults are plausible values for a ~60 kg humanoid; a robot overrides
them from its truth file.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from zmpkit._validate import finite, finite_array, non_negative, positive
from zmpkit.errors import ParameterError

__all__ = ["SensorParams", "TrialVariability"]


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
