"""zmpkit.control: ankle-strategy ZMP controllers for standing balance (paper A Fig. 9, 19).

- :mod:`~zmpkit.control.schedule`: :class:`GainSchedule`, the DLIPM's k_a and B_a as a
  smooth surface of the ZMP target, from the identified error model;
- :mod:`~zmpkit.control.dlipm_controller`: :class:`DlipmController`, the scheduled DLIPM
  producing the ankle angle, with a real-time-safe ``step()``;
- :mod:`~zmpkit.control.dlipm_feedback`: :class:`DlipmFeedbackController`, the scheduled
  DLIPM plus a clamped, anti-windup PI on the measured ZMP (:class:`ZmpFeedbackGains`);
- :mod:`~zmpkit.control.lipm_controller`: the classic :class:`LipmController` baseline
  (θ = asin(x_ref/l), optional PID on the measured ZMP) and
  :class:`LinearCorrectionController` (one constant correction from the fitted slope).
"""

from __future__ import annotations

from zmpkit.control.dlipm_controller import PAPER_A_TIME_SCALE, DlipmController, support_interval
from zmpkit.control.dlipm_feedback import DlipmFeedbackController, ZmpFeedbackGains
from zmpkit.control.lipm_controller import LinearCorrectionController, LipmController, PidGains
from zmpkit.control.schedule import DEFAULT_ZETA, GainSchedule, paper_a_coded_gains

__all__ = [
    "DEFAULT_ZETA",
    "PAPER_A_TIME_SCALE",
    "DlipmController",
    "DlipmFeedbackController",
    "GainSchedule",
    "LinearCorrectionController",
    "LipmController",
    "PidGains",
    "ZmpFeedbackGains",
    "paper_a_coded_gains",
    "support_interval",
]
