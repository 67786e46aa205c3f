r"""Watching a trial's hold from its sensors: extend it until settled, end it before a fall.

An operator of a real robot watches the measured ZMP while a lean is held: a response that
still creeps is held longer, and a creep that carries the robot toward the edge of its feet
is ended before it falls. :class:`HoldMonitor` does the same from what a real robot records —
both feet's F-T wrenches and the sensor mounts — and from design data (the support polygon):

- **settled**: from ``hold_s`` on, every :data:`CHECK_PERIOD_S`, the post-step ZMP (start-up
  offset removed) goes through :func:`~zmpkit.signals.steady_state`; once it is settled
  (including its creep check, with :data:`MONITOR_CREEP_MARGIN` of its tolerance) the trial
  ends. At ``max_hold_s`` it ends unsettled, with
  the detector's status and drift rate: "did not settle within H s (drift X mm/s)".
- **tipping**: the mean over the last :data:`TIP_AVERAGE_S` of the ZMP passes
  :data:`TIP_EDGE_FRACTION` of the way from the polygon's centre to its edge, or a foot
  carries less than :data:`LIFT_LOAD_FRACTION` of the weight (about to lift: the double-support
  lean is lost):

  .. math:: |\bar p - p_c| > f_{edge}\,(p_{edge} - p_c) \quad\text{or}\quad
      \min(\bar F_{z,R}, \bar F_{z,L}) < f_{lift} (\bar F_{z,R} + \bar F_{z,L})

  checked every :data:`TIP_CHECK_PERIOD_S` from the step on.

Without ``max_hold_s`` the hold is fixed (``hold_s``) and only the tipping check acts.
"""

from __future__ import annotations

import bisect
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.sensors import SensorMount, zmp_series
from zmpkit.signals import PLANES, SteadyState, StepTrial, steady_state
from zmpkit.signals.steady_state import CREEP_MIN_M, CREEP_TOLERANCE_FRACTION

__all__ = [
    "CHECK_PERIOD_S",
    "HOLD_ENDS",
    "LIFT_LOAD_FRACTION",
    "MONITOR_CREEP_MARGIN",
    "TIP_AVERAGE_S",
    "TIP_CHECK_PERIOD_S",
    "TIP_EDGE_FRACTION",
    "HoldEnd",
    "HoldMonitor",
]

CHECK_PERIOD_S = 1.0
"""How often an extensible hold asks whether the ZMP has settled [s]."""
TIP_CHECK_PERIOD_S = 0.1
"""How often the tipping check runs [s]."""
TIP_AVERAGE_S = 0.25
"""The tipping check reads the mean ZMP and loads over this much of the end [s]."""
TIP_EDGE_FRACTION = 0.85
"""A ZMP this far of the way from where it stood before the step to the support edge it
heads for ends the trial [-] (from the standing ZMP, not the polygon's centre: a robot
whose ankles sit near its heels stands near the heel edge)."""
LIFT_LOAD_FRACTION = 0.02
"""A foot carrying less than this fraction of the weight is about to lift [-]."""
MONITOR_CREEP_MARGIN = 0.8
"""The monitor ends a hold only on a creep within this fraction of the detector's tolerance,
so a trial it ends as settled is settled for the evaluation too, whose offset and window
differ by rounding [-]."""
HOLD_ENDS = ("hold", "settled", "hold_limit", "tipping")
"""How a trial's hold ended: fixed hold over, settled, extended to its limit, or tipping."""


@dataclass(frozen=True)
class HoldEnd:
    """How a trial's hold ended.

    Attributes:
        kind: one of :data:`HOLD_ENDS`.
        note: what was seen, in words (empty for a fixed hold that ended normally).
        hold_s: recorded time after the step when it ended [s].
    """

    kind: str
    note: str
    hold_s: float


class HoldMonitor:
    """Reads a trial's wrenches as they are recorded and says when its hold should end.

    Args:
        plane: ``"sagittal"`` (ZMP x) or ``"frontal"`` (ZMP y).
        target_m: the ZMP target [m].
        t_step_s: time of the step [s].
        startup_window_s: quiet standing before the step, whose mean ZMP is the offset [s].
        hold_s: the hold before the first settled check [s].
        max_hold_s: the longest hold [s]; None: the hold is fixed at ``hold_s``.
        mounts: the feet's F-T sensor mounts.
        polygon: the support extent in this plane (low, high) [m].
        contact_threshold_n: a foot is in contact above this world F_z [N] (the robot's:
            :attr:`~zmpkit.robots.robot.Robot.contact_force_threshold_n`).
    """

    def __init__(
        self,
        plane: str,
        target_m: float,
        t_step_s: float,
        startup_window_s: float,
        hold_s: float,
        max_hold_s: float | None,
        mounts: Mapping[str, SensorMount],
        polygon: tuple[float, float],
        contact_threshold_n: float,
    ) -> None:
        self._contact_threshold_n = contact_threshold_n
        self._axis = PLANES.index(plane)
        self._plane, self._target, self._t_step = plane, target_m, t_step_s
        self._startup = (t_step_s - startup_window_s, t_step_s)
        self._hold, self._max_hold = hold_s, max_hold_s
        self._mounts = mounts
        self._polygon = polygon
        self._offset: float | None = None
        self._time: list[float] = []
        self._zmp = np.empty(0)
        self._fz = np.empty((0, 2))
        self._pending: list[NDArray[np.float64]] = []
        self._next_tip = t_step_s
        self._next_check = t_step_s + hold_s
        self.end: HoldEnd | None = None

    @property
    def end_time_s(self) -> float:
        """The latest end of the trial [s]: the step plus the longest hold."""
        return self._t_step + (self._hold if self._max_hold is None else self._max_hold)

    def update(self, time: float, right: NDArray[np.float64], left: NDArray[np.float64]) -> bool:
        """Take one recorded sample (wrenches in the sensor frames [N, N·m]); True: stop now."""
        self._time.append(time)
        self._pending.append(np.concatenate([right, left]))
        if time < self._t_step:
            return False
        if time >= self._next_tip - 1e-9:
            self._next_tip += TIP_CHECK_PERIOD_S
            self._read_pending()
            if self._tipping(time):
                return True
        return self._hold_over(time)

    def _read_pending(self) -> None:
        """ZMP and vertical loads of the samples taken since the last check."""
        if not self._pending:
            return
        rows = np.vstack(self._pending)
        times = self._time[len(self._zmp) :]
        series = zmp_series(
            times,
            rows[:, :6],
            rows[:, 6:],
            self._mounts["right"],
            self._mounts["left"],
            contact_threshold_n=self._contact_threshold_n,
        )
        self._zmp = np.concatenate([self._zmp, series.zmp[:, self._axis]])
        self._fz = np.vstack([self._fz, np.column_stack([series.fz_right, series.fz_left])])
        self._pending = []
        if self._offset is None:
            t, z = np.asarray(self._time), self._zmp
            inside = (t >= self._startup[0]) & (t <= self._startup[1]) & np.isfinite(z)
            self._offset = float(np.mean(z[inside])) if inside.any() else 0.0

    def _tipping(self, time: float) -> bool:
        first = bisect.bisect_left(self._time, time - TIP_AVERAGE_S)
        z, fz = self._zmp[first:], self._fz[first:]
        after = time - self._t_step
        if not np.all(np.isfinite(z)):
            note = f"no foot in contact at {after:.2f} s after the step"
            return self._stop("tipping", note, time)
        right, left = (float(v) for v in fz.mean(axis=0))
        low = min(right, left)
        if low < LIFT_LOAD_FRACTION * (right + left):
            side = "right" if right < left else "left"
            return self._stop(
                "tipping",
                f"the {side} foot carries {100 * low / (right + left):.1f} % of the weight "
                f"{after:.2f} s after the step (below {100 * LIFT_LOAD_FRACTION:g} %): about "
                "to lift; trial ended before the robot tips",
                time,
            )
        return self._edge(float(z.mean()), time, after)

    def _edge(self, zmp: float, time: float, after: float) -> bool:
        """Stop when the ZMP ``zmp`` [m] (world) is far towards the support edge it heads for.

        Far: :data:`TIP_EDGE_FRACTION` of the way from where it stood before the step.
        """
        low, high = self._polygon
        rest = self._offset or 0.0
        edge = high if zmp >= rest else low
        if abs(zmp - rest) <= TIP_EDGE_FRACTION * abs(edge - rest):
            return False
        return self._stop(
            "tipping",
            f"the ZMP reached {zmp - rest:.4f} m from where it stood {after:.2f} s after the "
            f"step, past {100 * TIP_EDGE_FRACTION:g} % of the way to the support edge "
            f"{edge - rest:.4f} m from there; trial ended before the robot tips",
            time,
        )

    def _hold_over(self, time: float) -> bool:
        if time < self._next_check - 1e-9:
            return False
        self._next_check += CHECK_PERIOD_S
        if self._max_hold is None:
            return False
        self._read_pending()
        steady = self._steady()
        after = time - self._t_step
        if steady.settled:
            return self._stop("settled", f"settled after a {after:.1f} s hold", time)
        if after >= self._max_hold - 1e-9:
            return self._stop("hold_limit", _not_settled(steady, after), time)
        return False

    def _steady(self) -> SteadyState:
        t = np.asarray(self._time[: len(self._zmp)])
        z = self._zmp - (self._offset or 0.0)
        trial = StepTrial(t, z, self._target, self._t_step, self._plane)
        return steady_state(
            trial,
            creep_fraction=MONITOR_CREEP_MARGIN * CREEP_TOLERANCE_FRACTION,
            creep_min_m=MONITOR_CREEP_MARGIN * CREEP_MIN_M,
        )

    def _stop(self, kind: str, note: str, time: float) -> bool:
        self.end = HoldEnd(kind, note, time - self._t_step)
        return True

    def finish(self, time: float) -> HoldEnd:
        """How the hold ended, the trial's last sample being at ``time`` [s]."""
        if self.end is None:
            self.end = HoldEnd("hold", "", time - self._t_step)
        return self.end


def _not_settled(steady: SteadyState, hold_s: float) -> str:
    """``did not settle within H s (drift X mm/s)`` and the detector's status and reason."""
    return (
        f"did not settle within {hold_s:.0f} s (drift {steady.drift_rate_mm_s:.3g} mm/s, "
        f"{steady.status}): {steady.reason}"
    )
