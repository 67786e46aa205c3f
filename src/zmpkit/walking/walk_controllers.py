r"""Walking controllers: what turns the planned walk and the robot's sensors into joint targets.

Every controller answers, once per motion frame, ``step(frame, measurement)``: the joint
targets of frame ``k`` from the sensors read at frame ``k - 1`` (one frame of latency, as on
a robot whose control loop runs at the motion-frame rate). Three are built in:

- :class:`OpenLoopWalk` (``open``): the IK of the planned pattern, played unchanged; nothing
  reads a sensor. Paper B's simulations before feedback.
- :class:`ZmpIpWalk` (``zmpip``): paper B's walk. The preview controller of the 3D-LIPM runs
  on the state of :mod:`zmpkit.walking.zmp_observer`, corrected every frame by the CoM the
  robot estimates from its encoders and IMU and by the ZMP of its F-T sensors
  (:mod:`zmpkit.walking.state_estimator`), less the multibody ZMP the design model
  predicts of the plan (:func:`~zmpkit.walking.multibody_zmp.expected_zmp_offset`) and
  low-passed (:mod:`zmpkit.walking.zmp_prefilter`); the whole-body IK then realises the
  observed plan's next CoM with the planned feet.
- :class:`DcmWalk` (``dcm``): the divergent-component-of-motion stabiliser of today's walking
  controllers (Englsberger et al. 2015; Caron et al., lipm_walking_controller, 2019), in the
  form a position-controlled robot can use (:mod:`zmpkit.walking.dcm_stabiliser`): a CoM
  correction ``Δc`` added to the planned CoM, driven by the error of the DCM ``ξ = c + ċ/ω``
  that an observer of the command error estimates from the encoders, IMU and F-T sensors,
  with a CoM admittance towards the ZMP it asks for. Foot damping control (off by default,
  :mod:`zmpkit.walking.foot_damping`) turns the stance ankles so that the feet's CoP tracks
  that ZMP ``p^d``.

Any of them may carry per-frame joint offsets (:class:`OffsetWalk`), such as the soft
servos' feed-forward of :mod:`zmpkit.walking.servo_feedforward`; on soft servos both
feedback walks also feed forward the torques of the ZMP shift they ask for
(:mod:`zmpkit.walking.zmp_shift_feedforward`, in :class:`OnlineWalk`).

Both feedback walks also keep their heading: the IMU's yaw turns the feet still to land back
to the plan (:mod:`zmpkit.walking.heading_feedback`).

Controllers read only :class:`~zmpkit.walking.measurement.WalkMeasurement` (encoders, IMU,
F-T) and the plan; the simulator's state is not theirs to see.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol, TypeAlias

import numpy as np
from numpy.typing import NDArray

from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.walking.dcm_parameters import DcmParameters
from zmpkit.walking.dcm_stabiliser import DcmStabiliser
from zmpkit.walking.foot_damping import FootDamping, ankle_joints
from zmpkit.walking.heading_feedback import HeadingFeedbackGains
from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.online_walk import OnlineWalk, SensorLayout, WalkPlant
from zmpkit.walking.step_adjustment import StepAdjustmentParameters
from zmpkit.walking.step_events import StepEvent
from zmpkit.walking.zmp_observer import ObservedPreviewControl, ZmpObserverParameters
from zmpkit.walking.zmp_prefilter import ZMP_FILTER_HZ, ZmpPrefilter

__all__ = [
    "CONTROLLERS",
    "DcmParameters",
    "DcmWalk",
    "OffsetWalk",
    "OpenLoopWalk",
    "ReferenceAdapter",
    "SensorLayout",
    "StepAdjustmentParameters",
    "WalkController",
    "ZmpIpWalk",
]

CONTROLLERS: tuple[str, ...] = ("zmpip", "dcm", "open")
"""Names of the walking controllers, the default first."""


class WalkController(Protocol):
    """A walking controller (module docstring).

    ``reads_sensors`` False lets the loop skip filling the measurement (open loop).
    """

    name: str
    reads_sensors: bool

    def step(self, frame: int, measurement: WalkMeasurement) -> NDArray[np.float64]:
        """Joint targets of ``frame`` [rad] (trajectory order) from the readings of ``frame-1``."""
        ...


ReferenceAdapter: TypeAlias = Callable[
    [int, NDArray[np.float64], Sequence[NDArray[np.float64]]], None
]
"""Adapts a preview controller's ZMP reference online from the measured ZMP.

``adapt(frame, zmp_in_world, reference_by_axis)`` learns from the measured ZMP (x, y) [m] of
``frame`` and rewrites the reference from it on. Paper B's Algorithm 2 is one
(:meth:`~zmpkit.compensate.algorithm2.Algorithm2Offsets.adapt`).
"""


class OpenLoopWalk:
    """Plays the planned trajectory; reads no sensor (``open``)."""

    name = "open"
    reads_sensors = False

    def __init__(self, trajectory: JointTrajectory) -> None:
        self.trajectory = trajectory

    def step(self, frame: int, measurement: WalkMeasurement) -> NDArray[np.float64]:
        """The planned joint angles of ``frame`` [rad]."""
        return self.trajectory.q_rad[frame]


class OffsetWalk:
    """A walking controller whose joint targets get a per-frame offset added.

    Args:
        inner: the controller.
        offsets_rad: the offset of each frame [rad], shape (N, J) in trajectory order; the
            last row holds beyond the end.
    """

    def __init__(self, inner: WalkController, offsets_rad: NDArray[np.float64]) -> None:
        self.inner = inner
        self.name = inner.name
        self.reads_sensors = inner.reads_sensors
        self.offsets_rad = np.asarray(offsets_rad, dtype=np.float64)
        self._targets = np.zeros(self.offsets_rad.shape[1])

    def step(self, frame: int, measurement: WalkMeasurement) -> NDArray[np.float64]:
        """The inner controller's targets of ``frame`` plus its offset [rad]."""
        row = self.offsets_rad[min(frame, self.offsets_rad.shape[0] - 1)]
        return np.add(self.inner.step(frame, measurement), row, out=self._targets)

    def step_events(self) -> tuple[StepEvent, ...]:
        """The inner controller's adjusted steps (none for the open loop)."""
        events = getattr(self.inner, "step_events", None)
        return () if events is None else events()


class ZmpIpWalk(OnlineWalk):
    """Paper B's walk: preview control on the observed cart-table state (``zmpip``).

    Args:
        plant: the planned walk, the design model, its IK settings, its sensors and the
            encoders' joints (:data:`~zmpkit.walking.online_walk.WalkPlant`).
        parameters: the observer's noise levels.
        heading_gains: the IMU yaw feedback to the footsteps (default gains; gain 0: off).
        reference_adapter: adapts the tracked ZMP reference online from the measured ZMP
            before each correction (paper B's Algorithm 2, line 3: the ZMP/IP controller
            walks on ``p'``); None: the plan's reference.
        stepping: the step adjustment's trigger and limits (default: off).
        expected_zmp_offset_in_world: per frame, the ZMP the design model's multibody
            dynamics put beside the cart table's on the planned motion (its multibody ZMP
            minus the plan's cart-table ZMP) [m], shape (N, 2); the observer reads the
            measured ZMP less it, so it reacts to what the plan does not already explain,
            not to the swinging legs every step
            (:func:`~zmpkit.walking.multibody_zmp.expected_zmp_offset`); None: nothing
            subtracted (:mod:`zmpkit.walking.zmp_prefilter`).
        zmp_filter_hz: the cut-off of the low-pass the observer reads the measured ZMP
            through [Hz] (:data:`~zmpkit.walking.zmp_prefilter.ZMP_FILTER_HZ`); None: none.
        servo_stiffness_nm_per_rad: the P gain of the robot's soft servos [N·m/rad]: the
            targets then carry the torques of the ZMP shift the controller asks for beyond
            the reference (:mod:`zmpkit.walking.zmp_shift_feedforward`); None: stiff servos.
    """

    name = "zmpip"

    def __init__(
        self,
        *plant: *WalkPlant,
        parameters: ZmpObserverParameters | None = None,
        heading_gains: HeadingFeedbackGains | None = None,
        reference_adapter: ReferenceAdapter | None = None,
        stepping: StepAdjustmentParameters | None = None,
        expected_zmp_offset_in_world: NDArray[np.float64] | None = None,
        zmp_filter_hz: float | None = ZMP_FILTER_HZ,
        servo_stiffness_nm_per_rad: float | None = None,
    ) -> None:
        super().__init__(*plant, heading_gains, stepping, servo_stiffness_nm_per_rad)
        pattern = plant[0]
        self.reference_adapter = reference_adapter
        self.zmp_prefilter = ZmpPrefilter(
            pattern.config.control_period_s, expected_zmp_offset_in_world, zmp_filter_hz
        )
        com = pattern.com
        initial = np.column_stack(
            [
                com.com_position_in_world[0],
                com.com_velocity_in_world[0],
                com.com_acceleration_in_world[0],
            ]
        )
        self.control = ObservedPreviewControl(
            pattern.gains, pattern.zmp_reference_in_world, initial, parameters
        )
        self.stepping.attach_reference(self.control.reference_by_axis)
        self.offset_in_world = np.full((pattern.time_s.size, 2), np.nan)
        """The estimated ZMP offset ``d̂`` of each frame [m], shape (N, 2)."""

    def _correct(self, frame: int) -> None:
        est = self.estimator
        adapter = self.reference_adapter
        if adapter is not None:
            adapter(frame - 1, est.zmp_in_world, self.control.reference_by_axis)
        k = self._before[frame]  # frame - 1 (the walk's frames are the plan's)
        zmp = self.zmp_prefilter.read(k, est.zmp_in_world)
        com = self.control.update(k, est.com_in_world, zmp)
        offset, offsets = self.control.offset_in_world, self.offset_in_world
        offsets[k, 0], offsets[k, 1] = offset.item(0), offset.item(1)
        targets = self.targets.com_position_in_world
        targets[frame, 0], targets[frame, 1] = com.item(0), com.item(1)
        if self.zmp_shift is not None:  # what the controller asks of the ZMP at ``frame``
            control, shift = self.control, self.zmp_shift_in_world
            reference = control.reference_by_axis
            shift[0] = control.model_zmp(0) - reference[0].item(frame)
            shift[1] = control.model_zmp(1) - reference[1].item(frame)


class DcmWalk(OnlineWalk):
    """The DCM stabiliser around the planned walk (``dcm``).

    Args:
        plant: the planned walk, the design model, its IK settings, its sensors and the
            encoders' joints (:data:`~zmpkit.walking.online_walk.WalkPlant`).
        parameters: gains and limits.
        heading_gains: the IMU yaw feedback to the footsteps (default gains; gain 0: off).
        stepping: the step adjustment's trigger and limits (default: off).
        servo_stiffness_nm_per_rad: the P gain of the robot's soft servos [N·m/rad]: the
            targets then carry the torques of the ZMP the stabiliser asks for beyond the
            reference (:mod:`zmpkit.walking.zmp_shift_feedforward`); None: stiff servos.
    """

    name = "dcm"

    def __init__(
        self,
        *plant: *WalkPlant,
        parameters: DcmParameters | None = None,
        heading_gains: HeadingFeedbackGains | None = None,
        stepping: StepAdjustmentParameters | None = None,
        servo_stiffness_nm_per_rad: float | None = None,
    ) -> None:
        super().__init__(*plant, heading_gains, stepping, servo_stiffness_nm_per_rad)
        pattern, model, ik_settings, sensors, _ = plant
        self.parameters = parameters or DcmParameters()
        com = pattern.com
        self.stabiliser = DcmStabiliser(
            com.com_position_in_world, com.com_velocity_in_world,
            com.com_acceleration_in_world, pattern.zmp_reference_in_world, com.com_height_m,
            self.dt, STANDARD_GRAVITY_MPS2, self.parameters,
        )  # fmt: skip
        self.stepping.replans_dcm = True
        self.stabiliser.reference_shift = self.stepping.dcm_reference.shift
        self._com_shift = self.stepping.dcm_reference.com_next
        self.desired_zmp_in_world = self.stabiliser.desired_zmp_in_world
        """The ZMP p^d the stabiliser asked for at each frame [m], shape (N, 2)."""
        self.foot_damping: FootDamping | None = None
        """The ankles' CoP tracking of ``p^d``, or None (off)."""
        if any(a > 0.0 for a in self.parameters.foot_damping.admittance_rad_per_n_m_s):
            ankles = {f: ankle_joints(model, sensors.sole_sites[f]) for f in self.estimator.feet}
            self.foot_damping = FootDamping(
                self.parameters.foot_damping, ankles, ik_settings.joint_names, self.dt
            )
            self._threshold_n = sensors.contact_threshold_n
            self._zmp_error = np.zeros(2)
            self._foot_yaw = np.zeros(len(ankles))

    def step(self, frame: int, measurement: WalkMeasurement) -> NDArray[np.float64]:
        """Joint targets of ``frame`` [rad]: the IK's, with the ankles' CoP tracking added."""
        q = OnlineWalk.step(self, frame, measurement)  # (super() would make an object)
        if self.foot_damping is not None:
            self.foot_damping.apply(q)
        return q

    def _correct(self, frame: int) -> None:
        k = self._before[frame]  # frame - 1 (the walk's frames are the plan's)
        est = self.estimator
        zmp = est.zmp_in_world
        shift = self.stabiliser.update(k, est.com_in_world, zmp)
        plan, targets = self.pattern.com.com_position_in_world, self.targets.com_position_in_world
        moved = self._com_shift  # the re-planned CoM of an adjusted step
        targets[frame, 0] = plan.item(frame, 0) + shift.item(0) + moved.item(0)
        targets[frame, 1] = plan.item(frame, 1) + shift.item(1) + moved.item(1)
        if self.zmp_shift is not None:  # what the stabiliser asks of the ZMP beyond the plan
            desired, reference = self.desired_zmp_in_world, self.pattern.zmp_reference_in_world
            self.zmp_shift_in_world[0] = desired.item(k, 0) - reference.item(k, 0)
            self.zmp_shift_in_world[1] = desired.item(k, 1) - reference.item(k, 1)
        if self.foot_damping is not None:
            np.subtract(self.desired_zmp_in_world[k], zmp, out=self._zmp_error)
            for i, yaws in enumerate(self._sole_yaws):
                self._foot_yaw[i] = yaws[min(k, yaws.shape[0] - 1)]
            self.foot_damping.update(
                self._zmp_error, est.force_z_n, self._foot_yaw, self._threshold_n
            )
