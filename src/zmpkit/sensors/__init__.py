"""ZMP from ankle force–torque sensors: mounts, the vectorised and the scalar paths, calibration.

- :mod:`~zmpkit.sensors.mount`: :class:`SensorMount`, a sensor's pose and height above the sole.
- :mod:`~zmpkit.sensors.zmp`: :func:`zmp_series`, :func:`combined_zmp`, :func:`foot_zmp` over
  time series (numpy, no loop over samples).
- :mod:`~zmpkit.sensors.fast`: :class:`DoubleSupportZmp`, one sample in pure Python floats for
  a 1 kHz control loop.
- :mod:`~zmpkit.sensors.calibration`: :class:`WrenchCalibration` (axes, signs, units, gain,
  offset) and offsets estimated from unloaded or standing windows.
"""

from __future__ import annotations

from zmpkit.sensors.calibration import (
    FORCE_UNIT_SCALE,
    MOMENT_UNIT_SCALE,
    WrenchCalibration,
    remove_zmp_offset,
    wrench_offset_from_unloaded_window,
    zmp_offset_from_standing_window,
)
from zmpkit.sensors.fast import DoubleSupportZmp
from zmpkit.sensors.mount import ROTATION_TOLERANCE, SensorMount, rpy_to_matrix
from zmpkit.sensors.zmp import (
    CONTACT_FORCE_THRESHOLD_N,
    CONTACT_THRESHOLD_RANGE_N,
    CombinedZmp,
    FootZmp,
    ZmpSeries,
    combined_zmp,
    contact_threshold,
    foot_zmp,
    moment_coefficients,
    zmp_series,
)

__all__ = [
    "CONTACT_FORCE_THRESHOLD_N",
    "CONTACT_THRESHOLD_RANGE_N",
    "FORCE_UNIT_SCALE",
    "MOMENT_UNIT_SCALE",
    "ROTATION_TOLERANCE",
    "CombinedZmp",
    "DoubleSupportZmp",
    "FootZmp",
    "SensorMount",
    "WrenchCalibration",
    "ZmpSeries",
    "combined_zmp",
    "contact_threshold",
    "foot_zmp",
    "moment_coefficients",
    "remove_zmp_offset",
    "rpy_to_matrix",
    "wrench_offset_from_unloaded_window",
    "zmp_offset_from_standing_window",
    "zmp_series",
]
