"""A feedback tick allocates nothing that lasts and no numpy temporaries.

What "allocates nothing" means here, for Python code (floats and loop iterators are heap
objects): measured with :mod:`tracemalloc` over 600 ticks of a 0.2 m/s walk (lift-offs
included) after one gait cycle of warm-up,

- **nothing is kept**: the traced memory after the ticks is within 1 KiB of before (a
  tick that kept one 2-vector would add 70 KiB);
- **no numpy temporaries**: the peak traced memory during any one tick stays under 512 B above
  its start. What remains is Python's own churn (a loop's iterator is 48 B, a ``range`` loop
  96 B, an array view 96 B); one ``(2, 3)`` numpy temporary with its result is over 300 B
  and the arithmetic of the first versions peaked at 3.7 KiB (the state estimator) and
  0.8 KiB (the ZMP observer with the preview sum).

Each part is measured alone: the state estimator, the ZMP/IP observer with its preview law,
the DCM stabiliser's law and the IMU heading feedback. The whole-body IK (mink's QP) is not
part of the estimator and law and allocates.
"""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable

import numpy as np
import pytest

from zmpkit.experiments.walk import sensor_layout
from zmpkit.experiments.walk_trial import read_measurement, start_pose
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.walk_controllers import DcmWalk, ZmpIpWalk

WARM_UP = 100  # a gait cycle: the heading feedback's ramp shapes are made once
TICKS = 600
MAX_PEAK_B = 512
MAX_KEPT_B = 1024


@pytest.fixture(scope="module")
def parts() -> dict[str, Callable[[int], None]]:
    """Each part's tick as a function of the frame."""
    pattern = generate_pattern(
        PatternConfig(command=WalkCommand(v_x=0.2), duration_s=8.0,
                      gait=GaitParameters(step_duration_s=0.5))
    )  # fmt: skip
    robot = get_robot(DEFAULT_WALK_ROBOT)
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    sim = robot.make_simulation("all", None, seed=0)
    start_pose(sim, trajectory)
    layout = sensor_layout(sim, settings.sole_sites)
    measurement = WalkMeasurement.empty(sim.joint_names, tuple(layout.sole_sites))
    read_measurement(sim, measurement)
    zmpip = ZmpIpWalk(pattern, model, settings, layout, sim.joint_names)
    dcm = DcmWalk(pattern, model, settings, layout, sim.joint_names)
    estimator = zmpip.estimator
    yaw = np.zeros(len(estimator.feet))
    soles = zmpip._soles

    def estimate(k: int) -> None:
        estimator.update(measurement, soles[k], yaw)

    def observe(k: int) -> None:
        zmpip.control.update(k, estimator.com_in_world, estimator.zmp_in_world)

    def stabilise(k: int) -> None:
        dcm.stabiliser.update(k, estimator.com_in_world, estimator.zmp_in_world)

    def heading(k: int) -> None:
        zmpip.heading.update(k, measurement.imu_quaternion)

    estimate(0)
    return {"estimator": estimate, "zmpip observer": observe, "dcm law": stabilise,
            "heading": heading}  # fmt: skip


@pytest.mark.parametrize("part", ["estimator", "zmpip observer", "dcm law", "heading"])
def test_a_tick_keeps_nothing_and_makes_no_numpy_temporaries(
    parts: dict[str, Callable[[int], None]], part: str
) -> None:
    tick = parts[part]
    for k in range(1, WARM_UP):
        tick(k)
    peaks = np.zeros(TICKS, dtype=np.int64)
    tracemalloc.start()
    try:
        before, _ = tracemalloc.get_traced_memory()
        for i in range(TICKS):
            start, _ = tracemalloc.get_traced_memory()
            tracemalloc.reset_peak()
            tick(WARM_UP + i)
            _, peak = tracemalloc.get_traced_memory()
            peaks[i] = peak - start
        after, _ = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert after - before <= MAX_KEPT_B, f"{part} kept {after - before} B over {TICKS} ticks"
    worst = int(peaks.max())
    assert worst < MAX_PEAK_B, f"{part}: a tick's peak {worst} B (tick {int(peaks.argmax())})"
