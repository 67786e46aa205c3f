"""The allocation-free feedback tick computes what the tick before it did, to the last bit.

A 3 s closed-loop ZMP/IP walk of the built-in walker (all effects) is simulated once and its
sensor readings recorded, with every sensor fault of the sweep in it: NaN F-T samples, an F-T
dropout (no foot in contact: no ZMP), a 500 N spike and a drifting gyro. The readings are
then replayed, tick by tick as :class:`~zmpkit.walking.walk_controllers.ZmpIpWalk` feeds
them, through the state estimator, the heading feedback and the ZMP/IP observer, and through
their copies as of commit 443946f (``tests/helpers/tick_reference.py``); each tick's outputs
must be equal bit for bit (NaN where NaN). Half-way, the ZMP reference of the periods to
come is rewritten in both, as paper B's Algorithm 2 does online.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np
import pytest
from numpy.typing import NDArray
from tests.helpers.tick_reference import ReferenceEstimator, ReferenceHeading, ReferenceObserver

from zmpkit.experiments.walk import sensor_layout
from zmpkit.experiments.walk_disturbances import SensorFault
from zmpkit.experiments.walk_trial import simulate_walk
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.heading_feedback import HeadingFeedback
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.state_estimator import KinematicStateEstimator
from zmpkit.walking.walk_controllers import SensorLayout, ZmpIpWalk
from zmpkit.walking.zmp_observer import ObservedPreviewControl

DURATION_S = 3.0
FAULTS = (
    SensorFault("ft_nan", 0.8),
    SensorFault("ft_dropout", 1.3),
    SensorFault("ft_spike", 1.9),
    SensorFault("gyro_bias"),
)
REWRITE_FRAME = 150  # where the reference of the periods to come is rewritten


@dataclass
class _Walk:
    """The recorded walk: its plan, where its sensors sit, and what the controller read."""

    pattern: WalkingPattern
    model: mujoco.MjModel
    layout: SensorLayout
    joint_names: tuple[str, ...]
    frames: list[int] = field(default_factory=list)
    readings: list[WalkMeasurement] = field(default_factory=list)


class _RecordingWalk:
    """A ZMP/IP walk that keeps a copy of every measurement it is given."""

    name = "zmpip"
    reads_sensors = True

    def __init__(self, inner: ZmpIpWalk, walk: _Walk) -> None:
        self.inner, self.walk = inner, walk

    def step(self, frame: int, measurement: WalkMeasurement) -> NDArray[np.float64]:
        m = measurement
        self.walk.frames.append(frame)
        self.walk.readings.append(
            WalkMeasurement(m.joint_names, m.feet, m.time_s, m.q_meas_rad.copy(),
                            m.imu_quaternion.copy(), m.gyro_rps.copy(),
                            m.force_in_sensor.copy(), m.moment_in_sensor.copy())
        )  # fmt: skip
        return self.inner.step(frame, measurement)


@pytest.fixture(scope="module")
def walk() -> _Walk:
    """The recorded walk (module docstring)."""
    pattern = generate_pattern(
        PatternConfig(command=WalkCommand(v_x=0.2), duration_s=DURATION_S,
                      gait=GaitParameters(step_duration_s=0.5))
    )  # fmt: skip
    robot = get_robot(DEFAULT_WALK_ROBOT)
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    sim = robot.make_simulation("all", None, seed=0)
    layout = sensor_layout(sim, settings.sole_sites)
    walk = _Walk(pattern, model, layout, sim.joint_names)
    inner = ZmpIpWalk(pattern, model, settings, layout, sim.joint_names)
    simulate_walk(sim, trajectory, controller=_RecordingWalk(inner, walk), faults=FAULTS)
    return walk


@dataclass
class _Chain:
    """A feedback tick's parts: state estimator, heading feedback, ZMP/IP observer."""

    estimator: Any
    heading: Any
    observer: Any

    @classmethod
    def of(cls, walk: _Walk, reference: bool) -> _Chain:
        """The parts as :class:`ZmpIpWalk` builds them, new or as of commit 443946f."""
        layout, pattern = walk.layout, walk.pattern
        com = pattern.com
        initial = np.column_stack([com.com_position_in_world[0], com.com_velocity_in_world[0],
                                   com.com_acceleration_in_world[0]])  # fmt: skip
        estimator = (ReferenceEstimator if reference else KinematicStateEstimator)(
            walk.model, walk.joint_names, layout.sole_sites, layout.sensor_sites,
            layout.imu_site, layout.contact_threshold_n, pattern.config.control_period_s,
        )  # fmt: skip
        heading = (ReferenceHeading if reference else HeadingFeedback)(pattern.feet)
        observer = (ReferenceObserver if reference else ObservedPreviewControl)(
            pattern.gains, pattern.zmp_reference_in_world, initial
        )
        return cls(estimator, heading, observer)

    def tick(self, walk: _Walk, frame: int, measurement: WalkMeasurement) -> list[Any]:
        """One tick as :meth:`ZmpIpWalk.step` runs it; every output, copied."""
        feet = walk.pattern.feet
        by_side = {"left": feet.left.position_in_world, "right": feet.right.position_in_world}
        n = walk.pattern.time_s.size
        last = min(frame - 1, n - 1)
        est, targets = self.estimator, self.heading.targets
        soles = np.array([by_side[f][last] for f in est.feet])
        yaws = {"left": targets.left.yaw_in_world, "right": targets.right.yaw_in_world}
        yaw = np.array([yaws[f][last] for f in est.feet])
        est.update(measurement, soles, yaw)
        self.heading.update(min(frame, n - 1), measurement.imu_quaternion)
        if frame == REWRITE_FRAME:  # an online adaptation of the reference still to come
            for axis, reference in enumerate(self.observer.reference_by_axis):
                reference[frame:] += 0.003 * (axis + 1)
        com = self.observer.update(frame - 1, est.com_in_world, est.zmp_in_world)
        h, o = self.heading, self.observer
        return [
            est.com_in_world, est.com_velocity_in_world, est.zmp_in_world, est.force_z_n,
            est.yaw_correction_rad, h.correction_rad, h.heading_error_rad,
            h.targets.left.yaw_in_world, h.targets.right.yaw_in_world,
            h.targets.torso_yaw_in_world, com, o.state, o.jerk_in_world, o.offset_in_world,
        ]  # fmt: skip


@pytest.mark.slow
def test_the_recorded_walk_meets_every_fault(walk: _Walk) -> None:
    forces = np.array([m.force_in_sensor for m in walk.readings])
    assert len(walk.frames) == walk.pattern.time_s.size - 1  # it did not fall
    assert np.isnan(forces).any()  # NaN samples
    assert (np.abs(forces).sum(axis=(1, 2)) == 0.0).any()  # no foot in contact
    assert np.nanmax(forces[..., 2]) > 400.0  # the spike


@pytest.mark.slow
def test_the_tick_computes_what_the_reference_tick_did(walk: _Walk) -> None:
    new, old = _Chain.of(walk, reference=False), _Chain.of(walk, reference=True)
    undefined_zmp = 0
    for frame, measurement in zip(walk.frames, walk.readings, strict=True):
        got, expected = new.tick(walk, frame, measurement), old.tick(walk, frame, measurement)
        for i, (a, b) in enumerate(zip(got, expected, strict=True)):
            np.testing.assert_array_equal(a, b, err_msg=f"frame {frame}, output {i}")
        undefined_zmp += bool(np.isnan(new.estimator.zmp_in_world).any())
    assert undefined_zmp > 0
