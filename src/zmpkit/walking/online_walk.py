"""The feedback walks' common loop: estimate, correct the next frame's CoM, solve the IK for it.

Every tick of a feedback walk (:class:`~zmpkit.walking.walk_controllers.ZmpIpWalk`,
:class:`~zmpkit.walking.walk_controllers.DcmWalk`) estimates the robot's CoM from its encoders,
IMU and the feet in contact (:mod:`zmpkit.walking.state_estimator`), turns the feet still to
land by the IMU's yaw (:mod:`zmpkit.walking.heading_feedback`), lets the step adjustment move
the next landing (:mod:`zmpkit.walking.step_adjustment`), has the walk correct its CoM target
(:meth:`OnlineWalk._correct`) and solves the whole-body IK for it. A tick allocates nothing
but the IK's own work.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TypeAlias

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.walking.early_touchdown import EarlyTouchdown
from zmpkit.walking.heading_feedback import HeadingFeedback, HeadingFeedbackGains
from zmpkit.walking.ik import IkSettings, WalkingIk
from zmpkit.walking.level_swing import LevelSwing
from zmpkit.walking.measured_footholds import MeasuredFootholds
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.state_estimator import KinematicStateEstimator
from zmpkit.walking.step_adjustment import StepAdjustment
from zmpkit.walking.step_adjustment_parameters import StepAdjustmentParameters
from zmpkit.walking.step_events import StepEvent
from zmpkit.walking.step_reach import step_reach
from zmpkit.walking.zmp_shift_feedforward import ZmpShiftFeedforward

__all__ = [
    "EARLY_TOUCHDOWN",
    "YAW_FROM_FEET",
    "ZMP_SHIFT_FEEDFORWARD",
    "OnlineWalk",
    "SensorLayout",
    "WalkPlant",
]


@dataclass(frozen=True)
class SensorLayout:
    """Where a robot's sensors sit on its design model (site names).

    Attributes:
        sole_sites: foot -> site at its sole centre (the footstep plan's foot point).
        sensor_sites: foot -> its F-T sensor's site.
        imu_site: the IMU's site (on the root body).
        contact_threshold_n: world ``F_z`` from which a foot is in contact [N].
    """

    sole_sites: dict[str, str]
    sensor_sites: dict[str, str]
    imu_site: str
    contact_threshold_n: float


YAW_FROM_FEET = True
"""Whether the feedback walks take the base's yaw from the feet in contact (not the IMU)."""

EARLY_TOUCHDOWN = True
"""Whether the feedback walks stop a swing sole's descent where it met the floor before its
planned touchdown (:mod:`zmpkit.walking.early_touchdown`)."""

ZMP_SHIFT_FEEDFORWARD = True
"""Whether the feedback walks of a robot with soft servos feed forward the torques of the ZMP
shift they ask for (:mod:`zmpkit.walking.zmp_shift_feedforward`)."""


class _OnlineTargets:
    """What the IK reads of a pattern: the CoM, the feet and their yaw, written frame by frame."""

    def __init__(self, pattern: WalkingPattern, heading: HeadingFeedback) -> None:
        feet = heading.targets  # the yaws the heading feedback writes, the soles' own copies
        self.feet = replace(
            feet,
            left=replace(feet.left, position_in_world=feet.left.position_in_world.copy()),
            right=replace(feet.right, position_in_world=feet.right.position_in_world.copy()),
        )
        self.com_position_in_world = pattern.com_position_in_world.copy()


WalkPlant: TypeAlias = tuple[
    WalkingPattern, mujoco.MjModel, IkSettings, SensorLayout, tuple[str, ...]
]
"""What every feedback walk is built on, in :class:`OnlineWalk`'s order: the planned walk (its
reference, gains, CoM and feet), the robot's design model (the IK's), the IK settings the plan
was solved with, where the sensors sit on that model, and the encoders' joints in the
measurement's order."""


class OnlineWalk:
    """A feedback walk: estimate, correct the CoM of the next frame, solve the IK for it.

    With ``servo_stiffness_nm_per_rad`` (the P gain of the robot's soft servos [N·m/rad]) the
    targets carry the torques of the ZMP shift the walk asks for beyond the reference, which
    :meth:`_correct` writes in :attr:`zmp_shift_in_world`
    (:mod:`zmpkit.walking.zmp_shift_feedforward`); None: stiff servos.
    """

    name = "online"
    reads_sensors = True

    def __init__(
        self,
        pattern: WalkingPattern,
        model: mujoco.MjModel,
        ik_settings: IkSettings,
        sensors: SensorLayout,
        joint_names: tuple[str, ...],
        heading_gains: HeadingFeedbackGains | None = None,
        stepping: StepAdjustmentParameters | None = None,
        servo_stiffness_nm_per_rad: float | None = None,
    ) -> None:
        self.pattern = pattern
        self.dt = pattern.config.control_period_s
        self.heading = HeadingFeedback(pattern.feet, heading_gains)
        """IMU yaw feedback to the feet still to land (:mod:`zmpkit.walking.heading_feedback`)."""
        self.targets = _OnlineTargets(pattern, self.heading)
        self.ik = WalkingIk(model, ik_settings)
        self.ik.set_targets(self.targets, 0)
        self.ik.solve(ik_settings.max_iterations * 10, self.dt)
        self.estimator = KinematicStateEstimator(
            model, joint_names, sensors.sole_sites, sensors.sensor_sites, sensors.imu_site,
            sensors.contact_threshold_n, self.dt,
        )  # fmt: skip
        feet = pattern.feet
        by_side = {"left": feet.left.position_in_world, "right": feet.right.position_in_world}
        self._soles = np.stack([by_side[f] for f in self.estimator.feet], axis=1)  # (N, F, 3)
        targets = self.heading.targets
        yaws = {"left": targets.left.yaw_in_world, "right": targets.right.yaw_in_world}
        self._sole_yaws = [yaws[f] for f in self.estimator.feet]  # written by the heading
        self._yaw_now = np.zeros(len(self._sole_yaws))
        self.omega = math.sqrt(STANDARD_GRAVITY_MPS2 / pattern.com.com_height_m)
        self.com_target_in_world = np.full((pattern.time_s.size, 2), np.nan)
        """The CoM each frame was commanded to [m], shape (N, 2)."""
        self.com_estimate_in_world = np.full((pattern.time_s.size, 2), np.nan)
        """The estimated CoM of each frame [m], shape (N, 2)."""
        # What a tick reads and writes, made once (a tick makes no numpy object but the IK's).
        self._frames = self._soles.shape[0]
        end = self._frames - 1  # frame -> the frame before and the frame itself, clamped to
        self._before = [min(f - 1, end) for f in range(self._frames + 1)]  # the plan's end:
        self._clamped = [min(f, end) for f in range(self._frames + 1)]  # ints made once
        self._sole_rows = list(self._soles)  # each frame's (F, 3) planned soles, a view
        self._yaw_sources = tuple(enumerate(self._sole_yaws))
        self._q_sources = tuple(enumerate(self.ik.qadr))  # (target index, qpos address)
        self._q_targets = np.zeros(len(self.ik.qadr))
        self._ik_qpos = self.ik.configuration.data.qpos  # the IK's own (mink's ``q`` copies)
        stepping = stepping or StepAdjustmentParameters(enabled=False)
        reach = step_reach(
            model, ik_settings, self._ik_qpos.copy(),
            pattern.config.limits.min_foot_separation_m, stepping.reach_margin,
        )  # fmt: skip
        sides = {"left": self.targets.feet.left, "right": self.targets.feet.right}
        self.stepping = StepAdjustment(
            pattern, self.estimator.feet, reach, stepping,
            {f: sides[f].position_in_world for f in self.estimator.feet}, self._soles,
        )  # fmt: skip
        """The step adjustment (:mod:`zmpkit.walking.step_adjustment`)."""
        footholds = MeasuredFootholds(self.estimator, stepping.touchdown_contact_fraction)
        self.stepping.attach_footholds(footholds)
        self.level_swing = LevelSwing(stepping.enabled and stepping.level_swing)
        """The swing soles' pitch (:mod:`zmpkit.walking.level_swing`)."""
        self._foot_heights = tuple(
            (i, sides[f].position_in_world) for i, f in enumerate(self.ik.feet)
        )
        planned = {"left": pattern.feet.left, "right": pattern.feet.right}
        self.early_touchdown: EarlyTouchdown | None = None
        """The early touchdowns' held sole heights (:mod:`zmpkit.walking.early_touchdown`)."""
        if EARLY_TOUCHDOWN:
            self.early_touchdown = EarlyTouchdown(
                [planned[f].position_in_world[:, 2] for f in self.estimator.feet],
                [sides[f].position_in_world[:, 2] for f in self.estimator.feet],
                self.dt,
            )

        self.zmp_shift: ZmpShiftFeedforward | None = None
        """The soft servos' feed-forward of the ZMP shift (None: stiff servos)."""
        if servo_stiffness_nm_per_rad is not None and ZMP_SHIFT_FEEDFORWARD:
            self.zmp_shift = ZmpShiftFeedforward(
                model, self.ik.configuration.data,
                [sensors.sole_sites[f] for f in self.estimator.feet], ik_settings.joint_names,
                servo_stiffness_nm_per_rad, self.dt, pattern.config.gait.step_duration_s,
            )  # fmt: skip
        self.zmp_shift_in_world = [0.0, 0.0]
        """The ZMP shift (x, y) the walk asks for beyond the reference [m], written by
        :meth:`_correct` when :attr:`zmp_shift` is set."""

    def step_events(self) -> tuple[StepEvent, ...]:
        """The steps this walk adjusted so far (:class:`StepEvent`)."""
        return self.stepping.events()

    def _correct(self, frame: int) -> None:
        """Write the CoM target of ``frame`` into ``self.targets`` (estimates are current)."""
        raise NotImplementedError

    def _level_feet(self, frame: int, measurement: WalkMeasurement) -> None:
        """Each sole's pitch target of ``frame``: the trunk's pitch off a foot in the air."""
        level = self.level_swing
        if not level.enabled:
            return
        level.update(measurement.imu_quaternion)
        pitch = self.ik.foot_pitch_rad
        for i, position in self._foot_heights:
            pitch[i] = level.foot_pitch_rad(position.item(frame, 2))

    def step(self, frame: int, measurement: WalkMeasurement) -> NDArray[np.float64]:
        """Joint targets of ``frame`` [rad] from the readings of ``frame - 1``."""
        before, clamped = self._before, self._clamped
        last = before[frame] if frame < len(before) else self._frames - 1
        now = clamped[frame] if frame < len(clamped) else self._frames - 1
        yaw = None
        if YAW_FROM_FEET:
            yaw = self._yaw_now
            for i, planned in self._yaw_sources:
                yaw[i] = planned.item(last)
        self.estimator.update(measurement, self._sole_rows[last], yaw)
        com, estimates = self.estimator.com_in_world, self.com_estimate_in_world
        estimates[last, 0], estimates[last, 1] = com.item(0), com.item(1)
        self.heading.update(now, measurement.imu_quaternion)
        omega, velocity = self.omega, self.estimator.com_velocity_in_world
        self.stepping.update(
            now,
            last,
            com.item(0) + velocity.item(0) / omega,
            com.item(1) + velocity.item(1) / omega,
        )
        self._correct(frame)
        targets, commanded = self.targets.com_position_in_world, self.com_target_in_world
        commanded[frame, 0], commanded[frame, 1] = targets.item(frame, 0), targets.item(frame, 1)
        self._level_feet(frame, measurement)
        if self.early_touchdown is not None:
            est = self.estimator
            self.early_touchdown.update(now, est.force_z_n, est.threshold_n)
        self.ik.set_targets(self.targets, frame)
        self.ik.solve(self.ik.settings.max_iterations, self.dt)
        q, q_targets = self._ik_qpos, self._q_targets
        for j, address in self._q_sources:  # element by element: take() makes temporaries
            q_targets[j] = q.item(address)
        if self.zmp_shift is not None:
            x, y = self.zmp_shift_in_world
            est = self.estimator
            self.zmp_shift.apply(q_targets, x, y, est.force_z_n, est.threshold_n)
        return q_targets
