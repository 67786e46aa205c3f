"""The "linear" ZMP reference of paper B, sampled at the control period.

In single support the reference sits at the centre of the stance sole; in double support it
moves on a straight line, at constant speed, from the centre of the foot that is being
unloaded to the centre of the foot that takes the weight. A robot may plan its ZMP at
another point of each sole, ``forward_m`` ahead of the centre along the sole (a robot whose
ankles sit far behind its sole centres and bend little: the Berkeley Humanoid); "centre"
then reads that point. Before the first and after the
last weight transfer it rests midway between the feet. Every sample therefore lies inside
the stance sole (single support) or the convex hull of both soles (double support).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.footsteps import Footstep, FootstepPlan

__all__ = ["ZmpReference", "linear_zmp_reference", "sample_times"]

#: Slack when deciding how many samples fit into a duration [-], in units of dt.
SAMPLE_COUNT_SLACK = 1e-9


@dataclass(frozen=True)
class ZmpReference:
    """A sampled ZMP reference.

    Attributes:
        time_s: sample times, starting at 0 [s], shape (N,).
        zmp_x_in_world: reference x [m], shape (N,).
        zmp_y_in_world: reference y [m], shape (N,).
        dt_s: sampling period [s].
    """

    time_s: NDArray[np.float64]
    zmp_x_in_world: NDArray[np.float64]
    zmp_y_in_world: NDArray[np.float64]
    dt_s: float

    @property
    def zmp_in_world(self) -> NDArray[np.float64]:
        """The reference as an (N, 2) array [m]."""
        return np.column_stack([self.zmp_x_in_world, self.zmp_y_in_world])


def sample_times(duration_s: float, dt_s: float) -> NDArray[np.float64]:
    """Sample times ``0, dt, 2 dt, ...`` up to and including ``duration_s`` [s].

    Args:
        duration_s: length of the time span [s], >= 0.
        dt_s: sampling period [s], > 0.
    """
    duration = _validate.non_negative("duration_s", duration_s, "s")
    dt = _validate.positive("dt_s", dt_s, "s")
    count = int(np.floor(duration / dt + SAMPLE_COUNT_SLACK)) + 1
    return np.arange(count, dtype=np.float64) * dt


def _point(foot: Footstep, forward_m: float) -> tuple[float, float]:
    """The point ``forward_m`` [m] ahead of the sole centre of ``foot`` along its heading."""
    return foot.x + forward_m * math.cos(foot.yaw), foot.y + forward_m * math.sin(foot.yaw)


def _knots(plan: FootstepPlan, forward_m: float) -> tuple[list[float], list[float], list[float]]:
    """Times [s] and positions [m] of the corners of the piecewise-linear reference."""
    (lx, ly), (rx, ry) = _point(plan.initial_left, forward_m), _point(plan.initial_right, forward_m)
    times, xs, ys = [0.0], [(lx + rx) / 2], [(ly + ry) / 2]
    for k, step in enumerate(plan.steps):
        x, y = _point(plan.stance_before(k), forward_m)
        transfer_start = plan.steps[k - 1].t_end if k else plan.walk_start_s
        times += [transfer_start, step.t_start]
        xs += [xs[-1], x]
        ys += [ys[-1], y]
    last = plan.steps[-1]
    final_left, final_right = plan.final_feet()
    (lx, ly), (rx, ry) = _point(final_left, forward_m), _point(final_right, forward_m)
    end_x, end_y = (lx + rx) / 2, (ly + ry) / 2
    times += [last.t_end, last.t_end + plan.gait.double_support_s, plan.duration_s]
    xs += [xs[-1], end_x, end_x]
    ys += [ys[-1], end_y, end_y]
    return times, xs, ys


def linear_zmp_reference(plan: FootstepPlan, dt_s: float, forward_m: float = 0.0) -> ZmpReference:
    """Sample the linear ZMP reference of a footstep plan.

    Args:
        plan: the footsteps and their timing.
        dt_s: sampling period [s] (paper B: 0.01 s).
        forward_m: where in each sole the reference sits, ahead of its centre along the
            sole [m] (paper B: 0, the centre).

    Returns:
        The reference on ``sample_times(plan.duration_s, dt_s)``.
    """
    dt = _validate.positive("dt_s", dt_s, "s")
    if dt > plan.gait.step_duration_s:
        raise ParameterError(
            f"dt_s must be <= the step duration {plan.gait.step_duration_s} s, got {dt} s"
        )
    time = sample_times(plan.duration_s, dt)
    knot_t, knot_x, knot_y = _knots(plan, forward_m)
    zmp_x = np.interp(time, knot_t, knot_x)
    zmp_y = np.interp(time, knot_t, knot_y)
    for array in (time, zmp_x, zmp_y):
        array.setflags(write=False)
    return ZmpReference(time, zmp_x, zmp_y, dt)
