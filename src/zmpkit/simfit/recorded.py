"""What a robot recorded in one experiment: the signals the simulator is fitted to.

Only signals a real robot records: the commanded joint angles, the joint encoders, the ZMP
from the ankle F-T sensors and the trunk tilt from the IMU.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.signals.time_series import Signal, TimeSeries

__all__ = ["RecordedSignals"]


@dataclass(frozen=True, eq=False)
class RecordedSignals:
    """What a robot recorded in one experiment, one row per sample.

    Attributes:
        time_s: sample times [s], shape (N,).
        joint_names: columns of the joint arrays.
        q_cmd_rad: commanded joint angles [rad], shape (N, J).
        q_meas_rad: joint encoders [rad], shape (N, J).
        zmp_m: ZMP from the F-T sensors, world x and y [m], shape (N, 2); NaN without contact.
        trunk_tilt_rad: trunk tilt from the IMU in the experiment's plane (pitch for walks
            and sagittal steps, roll for frontal steps) [rad], shape (N,).
    """

    time_s: NDArray[np.float64]
    joint_names: tuple[str, ...]
    q_cmd_rad: NDArray[np.float64]
    q_meas_rad: NDArray[np.float64]
    zmp_m: NDArray[np.float64]
    trunk_tilt_rad: NDArray[np.float64]

    def head(self, rows: int) -> RecordedSignals:
        """The first ``rows`` samples (all of them when ``rows`` is their number)."""
        if rows >= self.time_s.size:
            return self
        return RecordedSignals(
            self.time_s[:rows],
            self.joint_names,
            self.q_cmd_rad[:rows],
            self.q_meas_rad[:rows],
            self.zmp_m[:rows],
            self.trunk_tilt_rad[:rows],
        )

    @property
    def dt_s(self) -> float:
        """Median sample period [s]."""
        return float(np.median(np.diff(self.time_s)))

    def as_time_series(self) -> TimeSeries:
        """The recording as one time series (joints on their axes, ZMP and tilt in world)."""
        columns = []
        for k, joint in enumerate(self.joint_names):
            columns.append((Signal(f"{joint}_cmd", "rad", "joint"), self.q_cmd_rad[:, k]))
            columns.append((Signal(f"{joint}_meas", "rad", "joint"), self.q_meas_rad[:, k]))
        columns += [
            (Signal("zmp_x", "m", "world"), self.zmp_m[:, 0]),
            (Signal("zmp_y", "m", "world"), self.zmp_m[:, 1]),
            (Signal("trunk_tilt", "rad", "world"), self.trunk_tilt_rad),
        ]
        return TimeSeries.from_columns(self.time_s, columns)
