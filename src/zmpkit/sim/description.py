"""What the simulator needs to know about a robot besides its MJCF.

A :class:`RobotDescription` names the driven joints (in the robot's order), the foot F-T
sensors with their sole heights, the IMU sensors, the servo trajectory limits, and carries
the truth-side sensor errors when the S effect is on. Any robot, built-in or a user's MJCF,
enters the simulator through one of these.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.names import ft_site
from zmpkit.sim.sensor_errors import SensorParams, TrialVariability
from zmpkit.sim.servo import ServoLimits

__all__ = ["FootSensor", "ImuSensors", "RobotDescription"]


@dataclass(frozen=True)
class FootSensor:
    """A foot's 6-axis F-T sensor.

    Attributes:
        foot: the foot's name, e.g. ``"right"``.
        force_sensor: name of the MuJoCo ``force`` sensor.
        torque_sensor: name of the MuJoCo ``torque`` sensor (same site).
        site: the sensor site; its frame is the sensor frame (x forward, y left, z up).
        sole_height_m: height of the sensor frame above the sole [m].
    """

    foot: str
    force_sensor: str
    torque_sensor: str
    site: str
    sole_height_m: float

    @classmethod
    def named(cls, foot: str, sole_height_m: float) -> FootSensor:
        """The sensor of ``foot`` named by convention.

        Site ``zmpkit/{foot}_ft`` (:func:`~zmpkit.sim.names.ft_site`) with the force and
        torque sensors ``{foot}_ft_force`` and ``{foot}_ft_torque``.
        """
        return cls(foot, f"{foot}_ft_force", f"{foot}_ft_torque", ft_site(foot), sole_height_m)


@dataclass(frozen=True)
class ImuSensors:
    """Names of the IMU's MuJoCo sensors."""

    gyro: str = "imu_gyro"
    accelerometer: str = "imu_accel"
    orientation: str = "imu_quat"


@dataclass(frozen=True)
class RobotDescription:
    """A simulated robot: MJCF with effects applied plus the names the simulator reads.

    Attributes:
        name: robot name.
        mjcf: the model XML, effects already applied.
        driven_joints: joints with a servo, in the robot's order; each has an actuator of
            the same name whose control is ``gear * q_ref``.
        feet: the foot F-T sensors.
        effects: which effects the MJCF and the readings include.
        contact_force_threshold_n: a foot touches the floor while its world-frame vertical
            force is at least this [N] (the ZMP's contact rule, :mod:`zmpkit.sensors.zmp`).
            Required: it is the robot's (:attr:`zmpkit.robots.robot.Robot.\
            contact_force_threshold_n` states it; ``Robot.description`` copies it here for
            the simulator's readers).
        servo_limits: setpoint trajectory limits.
        imu: the IMU's sensor names.
        sensor_params: sensor errors (used when ``effects.sensors``).
        ft_offsets: foot → F-T offset (Fx, Fy, Fz, Tx, Ty, Tz); defaults to
            ``sensor_params.ft_offset`` for feet not listed.
        ft_gain_errors: foot → relative gain error per axis (6,) [-]; defaults to
            ``sensor_params.ft_gain_error`` on every axis for feet not listed.
        variability: what makes one trial differ from the next.
    """

    name: str
    mjcf: str
    driven_joints: tuple[str, ...]
    feet: tuple[FootSensor, ...]
    effects: EffectSet
    contact_force_threshold_n: float
    servo_limits: ServoLimits = field(default_factory=ServoLimits)
    imu: ImuSensors = field(default_factory=ImuSensors)
    sensor_params: SensorParams = field(default_factory=SensorParams)
    ft_offsets: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    ft_gain_errors: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    variability: TrialVariability = field(default_factory=TrialVariability)

    def ft_offset(self, foot: str) -> tuple[float, ...]:
        """The F-T offset of one foot's sensor [N, N·m]."""
        return tuple(self.ft_offsets.get(foot, self.sensor_params.ft_offset))

    def ft_gain_error(self, foot: str) -> tuple[float, ...]:
        """The relative gain error of each axis of one foot's sensor [-]."""
        return tuple(self.ft_gain_errors.get(foot, (self.sensor_params.ft_gain_error,) * 6))
