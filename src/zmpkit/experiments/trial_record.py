"""What one step / push trial recorded, at the F-T sensor rate (:mod:`zmpkit.experiments.trial`).

Both feet's wrenches in their sensor frames, the joint encoders, the commanded joint
setpoints and the IMU: what a real robot's experiment would log, nothing else of the
simulation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.signals.time_series import Signal, TimeSeries

__all__ = ["StepTrialRecord"]


@dataclass(frozen=True, eq=False)
class StepTrialRecord:
    r"""What one trial recorded; arrays have one row per F-T sample.

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        target_m: the ZMP target :math:`x_{ref}` [m].
        t_step_s: time the lean (and push) starts [s].
        lean_angle_rad: the commanded lean :math:`\arcsin(x_{ref}/l_{lean})` [rad].
        lean_length_m: the design lean length :math:`l_{lean}` [m].
        joint_names: the driven joints, order of ``encoders`` and ``commanded``.
        time: sample times [s], shape (N,).
        right_wrench: right F-T sensor (F_x, F_y, F_z, τ_x, τ_y, τ_z), sensor frame
            [N, N·m], shape (N, 6).
        left_wrench: left F-T sensor, same layout, (N, 6).
        encoders: joint encoders [rad], (N, J).
        commanded: commanded joint setpoints [rad], (N, J).
        imu: gyro x, y, z [rad/s], accelerometer x, y, z [m/s²], quaternion w, x, y, z [-], (N, 10).
        hold_end: how the hold ended, one of :data:`~zmpkit.experiments.hold.HOLD_ENDS`.
        hold_note: what the hold monitor saw, in words; empty for a fixed hold.
        qpos: the simulator's whole configuration (MuJoCo ``qpos``) per sample, shape
            (N, nq), only when the trial was asked to record it (``record_qpos``, e.g. for a
            video); not something a real robot reports, never written to a dataset.
    """

    plane: str
    target_m: float
    t_step_s: float
    lean_angle_rad: float
    lean_length_m: float
    joint_names: tuple[str, ...]
    time: NDArray[np.float64]
    right_wrench: NDArray[np.float64]
    left_wrench: NDArray[np.float64]
    encoders: NDArray[np.float64]
    commanded: NDArray[np.float64]
    imu: NDArray[np.float64]
    hold_end: str = "hold"
    hold_note: str = ""
    qpos: NDArray[np.float64] | None = None

    def as_time_series(self) -> TimeSeries:
        """The trial's samples as one time series (sensor-frame wrenches, joints, IMU)."""
        wrench = ("fx", "fy", "fz", "tx", "ty", "tz")
        units = ("N", "N", "N", "N·m", "N·m", "N·m")
        imu = [("gyro_x", "rad/s"), ("gyro_y", "rad/s"), ("gyro_z", "rad/s"),
               ("accel_x", "m/s^2"), ("accel_y", "m/s^2"), ("accel_z", "m/s^2"),
               ("quat_w", "-"), ("quat_x", "-"), ("quat_y", "-"), ("quat_z", "-")]  # fmt: skip
        columns = [
            (Signal(f"{side}_{axis}", unit, "sensor"), values[:, k])
            for side, values in (("right", self.right_wrench), ("left", self.left_wrench))
            for k, (axis, unit) in enumerate(zip(wrench, units, strict=True))
        ]
        for k, joint in enumerate(self.joint_names):
            columns.append((Signal(f"{joint}_meas", "rad", "joint"), self.encoders[:, k]))
            columns.append((Signal(f"{joint}_cmd", "rad", "joint"), self.commanded[:, k]))
        columns += [
            (Signal(name, unit, "base"), self.imu[:, k]) for k, (name, unit) in enumerate(imu)
        ]
        return TimeSeries.from_columns(self.time, columns)
