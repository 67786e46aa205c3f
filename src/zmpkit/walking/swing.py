r"""Swing-foot trajectories and torso yaw, sampled at the control period.

During a swing of duration ``T_ss`` the normalised time is ``tau = (t - t_lift) / T_ss``.
Horizontal position and yaw follow the minimum-jerk (quintic) blend, the height a sextic
bump whose peak at ``tau = 1/2`` is the step height ``h``:

.. math::

    s(\tau) = 10\tau^3 - 15\tau^4 + 6\tau^5, \qquad
    z(\tau) = 64\, h\, \tau^3 (1-\tau)^3 .

Both have zero velocity and zero acceleration at lift-off and touch-down, so the foot leaves
and meets the ground without a jump in velocity or acceleration. A foot on the ground stays
exactly where it was placed. The torso is upright; its yaw is the mean of the feet yaws.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.footsteps import Footstep, FootstepPlan
from zmpkit.walking.zmp_reference import sample_times

__all__ = [
    "DEFAULT_STEP_HEIGHT_M",
    "FeetTrajectories",
    "FootTrajectory",
    "foot_trajectories",
    "minimum_jerk",
    "swing_height",
]

#: Default swing height for a kid-size robot [m].
DEFAULT_STEP_HEIGHT_M = 0.02

# Polynomial coefficients in tau, lowest order first, and those of derivatives 0..3.
_MIN_JERK = np.polynomial.Polynomial([0.0, 0.0, 0.0, 10.0, -15.0, 6.0])
_BUMP = np.polynomial.Polynomial([0.0, 0.0, 0.0, 64.0, -192.0, 192.0, -64.0])  # 64 t^3 (1-t)^3
_MIN_JERK_DERIVATIVES = tuple(_MIN_JERK.deriv(k).coef for k in range(4))
_BUMP_DERIVATIVES = tuple(_BUMP.deriv(k).coef for k in range(4))


def minimum_jerk(tau: ArrayLike, derivative: int = 0) -> NDArray[np.float64]:
    """Minimum-jerk blend ``s(tau)`` from 0 to 1, or its ``derivative``-th derivative in tau.

    A time derivative is this divided by ``T_ss ** derivative`` (T_ss the swing time [s]).
    """
    coefficients = _MIN_JERK_DERIVATIVES[_check_order(derivative)]
    return np.asarray(np.polynomial.polynomial.polyval(np.asarray(tau, float), coefficients))


def swing_height(tau: ArrayLike, step_height_m: float, derivative: int = 0) -> NDArray[np.float64]:
    """Swing height ``64 h tau^3 (1 - tau)^3`` [m] (peak ``h`` at tau = 1/2), or a derivative."""
    coefficients = _BUMP_DERIVATIVES[_check_order(derivative)]
    bump = np.polynomial.polynomial.polyval(np.asarray(tau, float), coefficients)
    return np.asarray(step_height_m * bump)


def _check_order(derivative: int) -> int:
    valid = isinstance(derivative, int) and not isinstance(derivative, bool)
    if not valid or not 0 <= derivative < len(_MIN_JERK_DERIVATIVES):
        raise ParameterError(
            f"derivative must be an integer in 0..{len(_MIN_JERK_DERIVATIVES) - 1}, "
            f"got {derivative!r}"
        )
    return derivative


@dataclass(frozen=True)
class FootTrajectory:
    """Sampled motion of one sole centre.

    Attributes:
        position_in_world: (x, y, z) of the sole centre [m], shape (N, 3); z = 0 on the ground.
        yaw_in_world: sole heading, unwrapped [rad], shape (N,).
        in_contact: True while the foot is on the ground, shape (N,).
    """

    position_in_world: NDArray[np.float64]
    yaw_in_world: NDArray[np.float64]
    in_contact: NDArray[np.bool_]


@dataclass(frozen=True)
class FeetTrajectories:
    """Both feet and the torso yaw on one time grid.

    Attributes:
        time_s: sample times [s], shape (N,).
        left: the left foot.
        right: the right foot.
        torso_yaw_in_world: mean of the feet yaws [rad], shape (N,); roll = pitch = 0.
        step_height_m: peak swing height [m].
    """

    time_s: NDArray[np.float64]
    left: FootTrajectory
    right: FootTrajectory
    torso_yaw_in_world: NDArray[np.float64]
    step_height_m: float


def _foot(
    plan: FootstepPlan, side: str, time: NDArray[np.float64], height: float
) -> FootTrajectory:
    """Vectorised: each sample finds the last swing of this foot that started before it."""
    start = plan.initial_left if side == "left" else plan.initial_right
    placements: list[Footstep] = [start, *(s for s in plan.steps if s.side == side)]
    poses = np.array([(p.x, p.y, p.yaw) for p in placements])  # (m + 1, 3)
    lift = np.array([p.t_start for p in placements[1:]])
    land = np.array([p.t_end for p in placements[1:]])
    swing = np.maximum(np.searchsorted(lift, time, side="left") - 1, 0)  # lift < t strictly
    tau = np.clip((time - lift[swing]) / (land[swing] - lift[swing]), 0.0, 1.0)
    pose = poses[swing] + minimum_jerk(tau)[:, None] * (poses[swing + 1] - poses[swing])
    position = np.column_stack([pose[:, :2], swing_height(tau, height)])
    contact = (tau <= 0.0) | (tau >= 1.0)
    return FootTrajectory(_frozen(position), _frozen(pose[:, 2]), _frozen(contact))


def _frozen(array: NDArray) -> NDArray:
    array = np.ascontiguousarray(array)
    array.setflags(write=False)
    return array


def foot_trajectories(
    plan: FootstepPlan, dt_s: float, step_height_m: float = DEFAULT_STEP_HEIGHT_M
) -> FeetTrajectories:
    """Sample both feet and the torso yaw on ``sample_times(plan.duration_s, dt_s)``.

    Args:
        plan: the footsteps and their timing.
        dt_s: sampling period [s] (paper B: 0.01 s).
        step_height_m: peak swing height above the ground [m], >= 0.

    Returns:
        Feet positions, yaws and contact flags, and the torso yaw.
    """
    height = _validate.non_negative("step_height_m", step_height_m, "m")
    dt = _validate.positive("dt_s", dt_s, "s")
    if dt > plan.gait.single_support_s:
        raise ParameterError(
            f"dt_s must be <= the single-support time {plan.gait.single_support_s} s, got {dt} s"
        )
    time = sample_times(plan.duration_s, dt)
    left = _foot(plan, "left", time, height)
    right = _foot(plan, "right", time, height)
    torso_yaw = _frozen((left.yaw_in_world + right.yaw_in_world) / 2)
    time.setflags(write=False)
    return FeetTrajectories(time, left, right, torso_yaw, height)


def swing_edges(in_contact: NDArray[np.bool_]) -> dict[int, int]:
    """Lift-off frame → touch-down frame of each swing of one foot.

    A swing still in the air at the end touches down at ``in_contact.size``.
    """
    contact = np.asarray(in_contact, dtype=bool)
    lifts = np.flatnonzero(contact[:-1] & ~contact[1:]) + 1
    lands = np.flatnonzero(~contact[:-1] & contact[1:]) + 1
    edges = {}
    for lift in lifts:
        later = lands[lands > lift]
        edges[int(lift)] = int(later[0]) if later.size else contact.size
    return edges
