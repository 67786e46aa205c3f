"""What a walking robot's sensors give its controller at one control tick.

Only what a real humanoid has: joint encoders, the IMU (gyro and the orientation its filter
estimates) and the 6-axis F-T sensors of the feet, each wrench in its own sensor frame. No
pose of anything in the world: where the robot is follows from these and the footstep plan
(:mod:`zmpkit.walking.state_estimator`).

The measurement is a *buffer*: the robot (or the simulator) writes into it in place every
tick and the controller reads it, so a control loop allocates nothing. It is therefore the
one mutable record of this package; a copy is made only where one is kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["WalkMeasurement"]


@dataclass(eq=False)
class WalkMeasurement:
    """One tick of sensor readings, overwritten in place by the robot.

    Attributes:
        joint_names: the encoders' joints, in the order of ``q_meas_rad``.
        feet: the F-T sensors' feet, in the order of the wrench arrays.
        time_s: time of the reading [s].
        q_meas_rad: encoder joint angles [rad], shape (J,).
        imu_quaternion: the IMU's orientation in the world, (w, x, y, z) [-], shape (4,).
        gyro_rps: the IMU's angular velocity in its own frame [rad/s], shape (3,).
        force_in_sensor: each foot's F-T force on the robot, sensor frame [N], shape (F, 3).
        moment_in_sensor: each foot's F-T moment about the sensor origin, sensor frame
            [N·m], shape (F, 3).
    """

    joint_names: tuple[str, ...]
    feet: tuple[str, ...]
    time_s: float
    q_meas_rad: NDArray[np.float64]
    imu_quaternion: NDArray[np.float64]
    gyro_rps: NDArray[np.float64]
    force_in_sensor: NDArray[np.float64]
    moment_in_sensor: NDArray[np.float64]

    @classmethod
    def empty(cls, joint_names: tuple[str, ...], feet: tuple[str, ...]) -> WalkMeasurement:
        """A zeroed buffer for these joints and feet (IMU upright)."""
        return cls(
            joint_names=joint_names,
            feet=feet,
            time_s=0.0,
            q_meas_rad=np.zeros(len(joint_names)),
            imu_quaternion=np.array([1.0, 0.0, 0.0, 0.0]),
            gyro_rps=np.zeros(3),
            force_in_sensor=np.zeros((len(feet), 3)),
            moment_in_sensor=np.zeros((len(feet), 3)),
        )
