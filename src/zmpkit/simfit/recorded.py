"""What a robot recorded in one experiment: the signals the simulator is fitted to.

Only signals a real robot records: the commanded joint angles, the joint encoders, the ZMP
and each foot's vertical force from the ankle F-T sensors and the trunk tilt from the IMU. A
record, recorded or simulated, is one :class:`~zmpkit.signals.time_series.TimeSeries`
(:attr:`RecordedSignals.series`, columns ``{joint}_cmd`` for every joint, then
``{joint}_meas``, then ``zmp_x``, ``zmp_y``, ``force_z_right``, ``force_z_left`` and
``trunk_tilt``); the arrays the fit's cost compares are read-only views of its columns,
so the fit compares time series without a copy. A rollout that diverged before its first
sample is a series of no rows.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.signals.time_series import Signal, TimeSeries

__all__ = ["RecordedSignals"]


def _signals(joint_names: tuple[str, ...]) -> tuple[Signal, ...]:
    """The record's columns: commands, encoders, ZMP (world x, y), feet's loads, trunk tilt."""
    return (
        *(Signal(f"{joint}_cmd", "rad", "joint") for joint in joint_names),
        *(Signal(f"{joint}_meas", "rad", "joint") for joint in joint_names),
        Signal("zmp_x", "m", "world"),
        Signal("zmp_y", "m", "world"),
        Signal("force_z_right", "N", "world"),
        Signal("force_z_left", "N", "world"),
        Signal("trunk_tilt", "rad", "world"),
    )


@dataclass(frozen=True, eq=False)
class RecordedSignals:
    """What a robot recorded in one experiment, one row per sample (module docstring).

    Built from the arrays below, which it keeps as views of one :attr:`series`.

    Attributes:
        time_s: sample times [s], shape (N,).
        joint_names: columns of the joint arrays.
        q_cmd_rad: commanded joint angles [rad], shape (N, J).
        q_meas_rad: joint encoders [rad], shape (N, J).
        zmp_m: ZMP from the F-T sensors, world x and y [m], shape (N, 2); NaN without contact.
        trunk_tilt_rad: trunk tilt from the IMU in the experiment's plane (pitch for walks
            and sagittal steps, roll for frontal steps) [rad], shape (N,).
        force_z_n: each foot's vertical force on the robot from its F-T sensor, world z,
            right then left [N], shape (N, 2), NaN where not recorded (the default: none).
        series: the record as one time series; the arrays above are views of its columns.
    """

    time_s: NDArray[np.float64]
    joint_names: tuple[str, ...]
    q_cmd_rad: NDArray[np.float64]
    q_meas_rad: NDArray[np.float64]
    zmp_m: NDArray[np.float64]
    trunk_tilt_rad: NDArray[np.float64]
    force_z_n: NDArray[np.float64] = field(default_factory=lambda: np.zeros((0, 2)))
    series: TimeSeries = field(init=False, repr=False)

    def __post_init__(self) -> None:
        names = tuple(self.joint_names)
        j = len(names)
        time = np.asarray(self.time_s, dtype=np.float64).reshape(-1)
        table = np.empty((time.size, 2 * j + 5))
        table[:, :j] = np.asarray(self.q_cmd_rad, dtype=np.float64).reshape(time.size, j)
        table[:, j : 2 * j] = np.asarray(self.q_meas_rad, dtype=np.float64).reshape(time.size, j)
        table[:, 2 * j : 2 * j + 2] = np.asarray(self.zmp_m, dtype=np.float64).reshape(-1, 2)
        force = np.asarray(self.force_z_n, dtype=np.float64)
        table[:, 2 * j + 2 : 2 * j + 4] = force.reshape(-1, 2) if force.size else np.nan
        table[:, 2 * j + 4] = np.asarray(self.trunk_tilt_rad, dtype=np.float64).reshape(-1)
        self._view(TimeSeries(time, table, _signals(names)), names)

    def _view(self, series: TimeSeries, joint_names: tuple[str, ...]) -> None:
        """Keep ``series`` and make every array field a view of its columns."""
        j, values = len(joint_names), series.values
        for name, value in (
            ("series", series),
            ("joint_names", joint_names),
            ("time_s", series.time_s),
            ("q_cmd_rad", values[:, :j]),
            ("q_meas_rad", values[:, j : 2 * j]),
            ("zmp_m", values[:, 2 * j : 2 * j + 2]),
            ("force_z_n", values[:, 2 * j + 2 : 2 * j + 4]),
            ("trunk_tilt_rad", values[:, 2 * j + 4]),
        ):
            object.__setattr__(self, name, value)

    @classmethod
    def from_series(cls, series: TimeSeries, joint_names: tuple[str, ...]) -> RecordedSignals:
        """The record whose columns ``series`` holds (:func:`_signals`' order), not copied."""
        if series.signals != _signals(tuple(joint_names)):
            names = ", ".join(s.name for s in _signals(tuple(joint_names)))
            raise ParameterError(f"a record of joints {joint_names} has the columns {names}")
        record = cls.__new__(cls)
        record._view(series, tuple(joint_names))
        return record

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickled as its series (one table), not as the views of it."""
        return (RecordedSignals.from_series, (self.series, self.joint_names))

    def head(self, rows: int) -> RecordedSignals:
        """The first ``rows`` samples (all of them when ``rows`` is their number)."""
        if rows >= self.time_s.size:
            return self
        s = self.series
        return RecordedSignals.from_series(
            TimeSeries(s.time_s[:rows], s.values[:rows], s.signals), self.joint_names
        )

    @property
    def dt_s(self) -> float:
        """Median sample period [s]."""
        return float(np.median(np.diff(self.time_s)))

    def as_time_series(self) -> TimeSeries:
        """The recording as one time series (joints on their axes, ZMP and tilt in world)."""
        return self.series
