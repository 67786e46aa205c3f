"""IMU yaw feedback to the footsteps: a walk that keeps its heading.

A walking robot turns a little at every step (its feet slide about the vertical under the
swing leg's reaction), and an open-loop footstep plan lets these turns add up: the built-in
kid-size robot's straight 10 s walk ends 0.05–0.2 rad off its heading. The feedback here turns the
footsteps that are still to come back to the plan, as a walking controller's footstep
planner does with the IMU's yaw:

- Every frame the heading error is read from the IMU,
  e = (ψ_IMU − ψ_IMU,0) − (ψ_plan − ψ_plan,0) [rad]. At each lift-off k of a foot, e_k is its
  mean over the last two steps (one gait cycle: the torso's yaw sways left and right with the
  steps, and a sample at alternate lift-offs reads that sway as an error, which the loop
  then drives; with the first observer the sampled e_k happened to be small, with its
  successor the sampled loop made the heading worse, 0.044 → 0.063 rad), and the correction
  is integrated,
  c_{k+1} = clip(c_k + clip(−K_ψ e_k, ±Δc_max), ±c_max) [rad] (K_ψ [-/step]: the fraction of
  the error taken out per step; 0 < K_ψ < 1 converges without overshoot for a step-wise
  constant slip; Δc_max bounds the turn of one step).
- The lifted foot lands turned by c_{k+1} about its own vertical: its yaw target moves from
  its old offset to c_{k+1} over the swing (a cosine ramp, no jump), then holds it while it
  stands. The torso's yaw target is the mean of the feet's, as in the plan.

Positions are left as planned, so the step lengths and the ZMP reference do not change; the
corrected feet turn the robot's heading back, and its path with it. The clip c_max bounds
what a drifting gyroscope (an IMU whose yaw creeps) can do to the walk: at most a turn of
c_max. Larger turns of the feet (0.15 rad, 0.05 rad per step) made the DCM stabiliser's
0.2 m/s walk fall, which stands without the feedback.

Measured on the built-in kid-size walker with all effects (``zmpkit walk``, 10 s at
0.2 m/s): the zmpip walk's largest heading error drops from 0.028 to 0.019 rad with the
feedback, the DCM walk's from 0.214 to 0.115 rad (which still misses 0.05). With the
lift-off sample instead of the two-step mean, an earlier observer's walk went from 0.058 to
0.021 rad, and it cost two of sixteen 20 N sideways pushes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.sensors.imu import quaternion_yaw
from zmpkit.walking.scalar_limits import clamp
from zmpkit.walking.swing import FeetTrajectories, swing_edges

__all__ = ["HeadingFeedback", "HeadingFeedbackGains"]


@dataclass(frozen=True)
class HeadingFeedbackGains:
    """Gain and limit of the heading feedback (module docstring).

    Attributes:
        gain_per_step: K_ψ, the fraction of the heading error taken out per step [-]; 0
            switches the feedback off.
        max_correction_rad: c_max, the largest turn of the footsteps [rad].
        max_change_per_step_rad: Δc_max, the largest change of c at one step [rad].
    """

    gain_per_step: float = 0.5
    max_correction_rad: float = 0.08
    max_change_per_step_rad: float = 0.02

    def __post_init__(self) -> None:
        _validate.in_range("HeadingFeedbackGains.gain_per_step", self.gain_per_step, 0.0, 1.0)
        _validate.in_range(
            "HeadingFeedbackGains.max_correction_rad", self.max_correction_rad, 0.0, 0.5, "rad"
        )
        _validate.in_range(
            "HeadingFeedbackGains.max_change_per_step_rad", self.max_change_per_step_rad, 0.0,
            0.5, "rad",
        )  # fmt: skip


_SIDES = ("left", "right")


class _RampViews(NamedTuple):
    """What one lift-off writes: views into the offsets, the plan and the targets [rad]."""

    shape: NDArray[np.float64]  # the cosine ramp over the swing, 0 -> 1 [-]
    ramp: NDArray[np.float64]  # the foot's offset over the swing
    landed: NDArray[np.float64]  # the foot's offset after landing
    offset: NDArray[np.float64]  # the foot's offset from lift-off on
    plan_yaw: NDArray[np.float64]
    target_yaw: NDArray[np.float64]
    left: NDArray[np.float64]
    right: NDArray[np.float64]
    mean: NDArray[np.float64]  # the feet's mean offset
    plan_torso: NDArray[np.float64]
    target_torso: NDArray[np.float64]


class HeadingFeedback:
    """Turns the feet still to land so that the IMU's heading follows the plan.

    Args:
        feet: the planned feet (left, right) and torso yaw; not changed.
        gains: K_ψ and c_max.

    Attributes:
        targets: the feet the IK follows: the plan's positions, yaw targets with the
            corrections (arrays of its own, written frame by frame).
        correction_rad: c, the current correction [rad].
        heading_error_rad: e at each lift-off [rad] (NaN elsewhere), shape (N,).
    """

    def __init__(self, feet: FeetTrajectories, gains: HeadingFeedbackGains | None = None) -> None:
        self.gains = gains or HeadingFeedbackGains()
        self._plan = feet
        self.targets = replace(
            feet,
            left=replace(feet.left, yaw_in_world=feet.left.yaw_in_world.copy()),
            right=replace(feet.right, yaw_in_world=feet.right.yaw_in_world.copy()),
            torso_yaw_in_world=feet.torso_yaw_in_world.copy(),
        )
        n = feet.time_s.size
        self._offset = {"left": np.zeros(n), "right": np.zeros(n)}
        self._lift_offs = {
            side: swing_edges(getattr(feet, side).in_contact) for side in ("left", "right")
        }
        self.correction_rad = 0.0
        self.heading_error_rad = np.full(n, np.nan)
        self._imu_start: float | None = None
        self._last_yaw = 0.0
        self._turns = 0.0
        self._error_sum = 0.0  # Σ e since the last lift-off [rad]
        self._error_frames = 0
        self._last_step_mean: float | None = None  # mean e over the step before [rad]
        self._mean = np.zeros(n)
        self._last_frame = n - 1
        self._scalar = np.zeros(())  # a ramp's start or height [rad], written in place
        self._half = np.full((), 0.5)
        shapes: dict[int, NDArray[np.float64]] = {}  # per swing length [frames]
        self._ramps = {side: {lift: self._ramp_views(side, lift, land, shapes)
                              for lift, land in lifts.items()}
                       for side, lifts in self._lift_offs.items()}  # fmt: skip

    def _ramp_views(
        self, side: str, lift: int, land: int, shapes: dict[int, NDArray[np.float64]]
    ) -> _RampViews:
        """The views one lift-off writes, made with the plan (a lift-off makes none)."""
        swing = max(land - lift, 1)  # 0.5 - 0.5 cos(π j / n), j = 1..n
        if swing not in shapes:
            shapes[swing] = 0.5 - 0.5 * np.cos(np.pi * np.arange(1, swing + 1) / swing)
        offset = self._offset[side]
        m = min(swing, offset.size - lift)
        plan, target = getattr(self._plan, side), getattr(self.targets, side)
        return _RampViews(
            shape=shapes[swing][:m], ramp=offset[lift : lift + m], landed=offset[lift + m :],
            offset=offset[lift:], plan_yaw=plan.yaw_in_world[lift:],
            target_yaw=target.yaw_in_world[lift:], left=self._offset["left"][lift:],
            right=self._offset["right"][lift:], mean=self._mean[lift:],
            plan_torso=self._plan.torso_yaw_in_world[lift:],
            target_torso=self.targets.torso_yaw_in_world[lift:],
        )  # fmt: skip

    def _imu_heading(self, quat_wxyz: NDArray[np.float64]) -> float:
        """The IMU's yaw since the first reading, unwrapped [rad]."""
        yaw = quaternion_yaw(quat_wxyz)
        if self._imu_start is None:
            self._imu_start, self._last_yaw = yaw, yaw
        step = (yaw - self._last_yaw + math.pi) % (2.0 * math.pi) - math.pi
        self._turns += step
        self._last_yaw = yaw
        return self._turns

    def update(self, frame: int, imu_quaternion: NDArray[np.float64]) -> None:
        """Read the IMU before ``frame``; at a lift-off, correct that foot's landing yaw."""
        if self.gains.gain_per_step == 0.0:
            return
        heading = self._imu_heading(imu_quaternion)
        plan = self._plan.torso_yaw_in_world
        now = heading - (plan.item(min(frame, self._last_frame)) - plan.item(0))
        self._error_sum += now
        self._error_frames += 1
        for side in _SIDES:
            ramp = self._ramps[side].get(frame)
            if ramp is None:
                continue
            step_mean = self._error_sum / self._error_frames
            error = (
                step_mean
                if self._last_step_mean is None
                else (0.5 * (step_mean + self._last_step_mean))
            )  # the last two steps: one gait cycle, the torso's left-right sway cancels
            self._last_step_mean, self._error_sum, self._error_frames = step_mean, 0.0, 0
            self.heading_error_rad[frame] = error
            g = self.gains
            change = clamp(-g.gain_per_step * error, g.max_change_per_step_rad)
            self.correction_rad = clamp(self.correction_rad + change, g.max_correction_rad)
            self._ramp(ramp, side, frame)

    def _ramp(self, views: _RampViews, side: str, lift: int) -> None:
        """This foot's offset: a cosine ramp to c over the swing, then c until the end.

        Written in place through views made with the plan, with the ramp's scalars in a 0-d
        array (a Python float in a ufunc would become a numpy temporary).
        """
        start, goal, scalar = self._offset[side].item(lift), self.correction_rad, self._scalar
        scalar[()] = goal - start
        np.multiply(views.shape, scalar, out=views.ramp)
        scalar[()] = start
        np.add(views.ramp, scalar, out=views.ramp)
        views.landed.fill(goal)
        np.add(views.plan_yaw, views.offset, out=views.target_yaw)
        np.add(views.left, views.right, out=views.mean)  # the torso turns by the feet's mean
        np.multiply(views.mean, self._half, out=views.mean)
        np.add(views.plan_torso, views.mean, out=views.target_torso)
