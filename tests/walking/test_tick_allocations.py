"""A feedback tick creates no numpy array and keeps nothing.

What "allocates nothing" means here, for Python code (floats and a loop's iterator are heap
objects), measured with :mod:`tracemalloc` over 600 ticks of a 0.2 m/s walk (lift-offs
included) after 200 ticks of warm-up (the walk's 1 s of standing and its first step, whose
first lift-off and landing make a walk's first state once: 16 B once for the whole DCM walk
step when the window began at tick 100), each part of the tick alone:

- **no numpy object is created in a tick**: the peak traced memory during any tick, above
  its start, is below that of every tick that does nothing but make one numpy view
  (``a[1:3]``, the cheapest numpy array: 96 B of object, no data), measured in the same
  harness (whose own share is 0 B, 32 B once). A view,
  copy, result, numpy scalar or the 0-d array numpy makes of a Python float in a ufunc
  would each be at least that. What remains is Python's own churn: one loop's iterator
  (48 B; ``range`` loops, ``enumerate`` and ``min``/``max``, which make more, are not on the
  path). Floats and small tuples come from CPython's free lists and do not show; the one
  way a numpy object could hide is a tick that first frees as many bytes of objects made
  before it, which none of these parts does (they replace only floats and small ints).
- **nothing is kept**: after the 600 ticks the traced memory has grown no more than with a
  tick that does nothing (the harness's own loop and counters, 92 B; a tick that kept one
  float would add 14 KiB), and numpy's own allocations (its data buffers, traced in
  ``np.lib.tracemalloc_domain``) did not change at all.

Measured: the state estimator, the ZMP/IP observer with its preview law and the IMU heading
feedback each peak at 48–80 B a tick (one or two loop iterators, by the order the parts run;
before: 216 B, 272 B, and 80 B or 432 B at a lift-off),
the DCM stabiliser's law (:mod:`zmpkit.walking.dcm_stabiliser`) at 80 B (before: 272 B: a
view of its error state's row and ``min``/``max``), and the whole feedback steps of the
``zmpip`` and ``dcm`` walks around the whole-body IK, whose target setting and QP solve
are stubbed here (mink's, which allocate), the early touchdown hold included
(:mod:`zmpkit.walking.early_touchdown`: the harness's fixed readings load both feet, so it
holds each descending swing sole, 14 times in the ``zmpip`` step's 800 ticks): 80 B
(before: over 360 B — mink's ``q``
property copies the configuration, a view of the planned soles, row copies into the logs,
``min``, ``super()`` and frame arithmetic on ints above 256). The same steps with the step
adjustment of :mod:`zmpkit.walking.step_adjustment` triggered at every step (its capture,
the re-planned swing, the ZMP reference and DCM references re-planned at each touchdown;
their own test below). The same steps of a robot with soft servos, whose targets carry the
torques of the ZMP shift (:mod:`zmpkit.walking.zmp_shift_feedforward`, a gain of 20 N·m/rad
on this robot's model; both feet loaded by the harness's readings).
"""

from __future__ import annotations

import tracemalloc
from collections.abc import Callable

import numpy as np
import pytest
from numpy.typing import NDArray

from helpers.allocations import alone
from zmpkit.experiments.walk import sensor_layout
from zmpkit.experiments.walk_trial import read_measurement, start_pose
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.measurement import WalkMeasurement
from zmpkit.walking.multibody_zmp import expected_zmp_offset
from zmpkit.walking.step_adjustment import StepAdjustmentParameters
from zmpkit.walking.walk_controllers import DcmWalk, ZmpIpWalk

WARM_UP = 200  # past the walk's start (module docstring)
STEPPING_WARM_UP = 300  # past the heading feedback's clamp (test of the stepping ticks)
TICKS = 600

Tick = Callable[[int], object]


@pytest.fixture(scope="module")
def parts() -> dict[str, Tick]:
    """Each part's tick as a function of the frame, and two yardsticks."""
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
    soles = list(zmpip._soles)  # each frame's (F, 3) view, made before the ticks
    some = np.zeros(8)

    def estimate(k: int) -> None:
        estimator.update(measurement, soles[k], yaw)

    def observe(k: int) -> None:
        zmpip.control.update(k, estimator.com_in_world, estimator.zmp_in_world)

    def stabilise(k: int) -> None:
        dcm.stabiliser.update(k, estimator.com_in_world, estimator.zmp_in_world)

    def heading(k: int) -> None:
        zmpip.heading.update(k, measurement.imu_quaternion)

    # Whole feedback steps around the IK: separate walks whose IK does nothing (the QP is
    # mink's and allocates; everything the step does around it is measured).
    walks = {}
    # every step adjusted, and the swing soles levelled (zmpkit.walking.level_swing)
    always = StepAdjustmentParameters(trigger_dcm_error_m=(0.0, 0.0), level_swing=True)
    expected = expected_zmp_offset(model, trajectory, pattern.com.zmp_in_world)  # as walks do
    for name, walk in (
        ("zmpip step", ZmpIpWalk(pattern, model, settings, layout, sim.joint_names,
                                 expected_zmp_offset_in_world=expected)),
        ("dcm step", DcmWalk(pattern, model, settings, layout, sim.joint_names)),
        ("zmpip soft step", ZmpIpWalk(pattern, model, settings, layout, sim.joint_names,
                                      expected_zmp_offset_in_world=expected,
                                      servo_stiffness_nm_per_rad=20.0)),
        ("dcm soft step", DcmWalk(pattern, model, settings, layout, sim.joint_names,
                                  servo_stiffness_nm_per_rad=20.0)),
        ("zmpip stepping", ZmpIpWalk(pattern, model, settings, layout, sim.joint_names,
                                     stepping=always, expected_zmp_offset_in_world=expected)),
        ("dcm stepping", DcmWalk(pattern, model, settings, layout, sim.joint_names,
                                 stepping=always)),
    ):  # fmt: skip
        walk.ik.set_targets = _no_op  # type: ignore[method-assign]
        walk.ik.solve = _no_op  # type: ignore[method-assign]
        walks[name] = walk

    def zmpip_step(k: int) -> None:
        walks["zmpip step"].step(k, measurement)

    def dcm_step(k: int) -> None:
        walks["dcm step"].step(k, measurement)

    def zmpip_soft_step(k: int) -> None:
        walks["zmpip soft step"].step(k, measurement)

    def dcm_soft_step(k: int) -> None:
        walks["dcm soft step"].step(k, measurement)

    def zmpip_stepping(k: int) -> None:
        walks["zmpip stepping"].step(k, measurement)

    def dcm_stepping(k: int) -> None:
        walks["dcm stepping"].step(k, measurement)

    def nothing(k: int) -> None:
        return None

    def one_view(k: int) -> object:
        return some[1:3]

    estimate(0)
    return {"estimator": estimate, "zmpip observer": observe, "dcm law": stabilise,
            "heading": heading, "zmpip step": zmpip_step, "dcm step": dcm_step,
            "zmpip soft step": zmpip_soft_step, "dcm soft step": dcm_soft_step,
            "zmpip stepping": zmpip_stepping, "dcm stepping": dcm_stepping,
            "nothing": nothing, "one view": one_view}  # fmt: skip


def _no_op(*args: object) -> None:
    """Stands in for the IK's target setting and QP solve."""


def _run(
    tick: Tick, refill: bool = False, warm_up: int = WARM_UP
) -> tuple[NDArray[np.int64], int, int]:
    """Each tick's peak above its start, the bytes and the numpy bytes kept [B].

    Measured in a forked child (:func:`helpers.allocations.alone`): no other thread's
    allocations are counted. ``refill``: CPython's float free list is filled before each
    tick (:func:`_refill_floats`); ``warm_up`` ticks run before.
    """
    return alone(lambda: _measure(tick, refill, warm_up))


FLOAT_FREE_LIST = 100
"""CPython's float free list holds this many floats (``PyFloat_MAXFREELIST``) [-]."""


def _refill_floats() -> None:
    """Fill CPython's float free list, outside the tick.

    A tick's floats come from this list and do not show while it holds enough. The step
    adjustment's tick holds some sixty floats at once; when the ticks before it held fewer,
    the list runs dry and it reads 24 B a float as if it allocated (seen: three ticks in
    600 at 96 B, four floats; none with the list filled).
    """
    spare = [i + 0.5 for i in range(FLOAT_FREE_LIST + 20)]
    del spare


def _measure(
    tick: Tick, refill: bool = False, warm_up: int = WARM_UP
) -> tuple[NDArray[np.int64], int, int]:
    for k in range(1, warm_up):
        tick(k)
    frames = list(range(warm_up, warm_up + TICKS))  # the frames' ints exist before
    peaks = np.zeros(TICKS, dtype=np.int64)
    numpy_only = [tracemalloc.DomainFilter(inclusive=True, domain=np.lib.tracemalloc_domain)]
    tracemalloc.start()
    try:
        numpy_before = tracemalloc.take_snapshot().filter_traces(numpy_only)
        before = tracemalloc.get_traced_memory()[0]
        for i, k in enumerate(frames):
            if refill:
                _refill_floats()
            tracemalloc.reset_peak()
            start = tracemalloc.get_traced_memory()[0]
            tracemalloc.reset_peak()
            tick(k)
            peaks[i] = tracemalloc.get_traced_memory()[1] - start
        kept = tracemalloc.get_traced_memory()[0] - before
        numpy_after = tracemalloc.take_snapshot().filter_traces(numpy_only)
    finally:
        tracemalloc.stop()
    numpy_kept = sum(s.size_diff for s in numpy_after.compare_to(numpy_before, "filename"))
    return peaks, kept, numpy_kept


@pytest.fixture(scope="module")
def yardsticks(parts: dict[str, Tick]) -> tuple[int, int]:
    """The least peak of a tick that makes one numpy view, the bytes the harness keeps [B]."""
    view = int(_run(parts["one view"])[0].min())
    nothing, harness_kept, _ = _run(parts["nothing"])
    assert view >= 96 > int(nothing.max()), f"the harness misses a view ({view} B, {nothing})"
    return view, harness_kept


@pytest.mark.parametrize(
    "part",
    ["estimator", "zmpip observer", "dcm law", "heading", "zmpip step", "dcm step",
     "zmpip soft step", "dcm soft step"],
)  # fmt: skip
@pytest.mark.slow
def test_a_tick_creates_no_numpy_object_and_keeps_nothing(
    parts: dict[str, Tick], yardsticks: tuple[int, int], part: str
) -> None:
    one_view_peak, harness_kept = yardsticks
    peaks, kept, numpy_kept = _run(parts[part])
    worst = int(peaks.max())
    assert worst < one_view_peak, f"{part}: a tick's peak {worst} B, one view's {one_view_peak}"
    assert kept <= harness_kept, f"{part} kept {kept - harness_kept} B over {TICKS} ticks"
    assert numpy_kept == 0, f"{part} kept {numpy_kept} B of numpy data over {TICKS} ticks"


@pytest.mark.parametrize("part", ["zmpip stepping", "dcm stepping"])
@pytest.mark.slow
def test_a_stepping_tick_creates_no_numpy_object_and_keeps_nothing(
    parts: dict[str, Tick], yardsticks: tuple[int, int], part: str
) -> None:
    """The feedback steps with the step adjustment at work.

    The peaks are read with the float free list filled before each tick; what a tick keeps,
    without (the refills leave floats parked in the list). Measured from frame 300: in this
    walk the heading feedback reaches its clamp between frames 200 and 300 (its correction
    then becomes the clamp's own float: 24 B kept once, not the step adjustment's).
    """
    one_view_peak, harness_kept = yardsticks
    peaks = _run(parts[part], refill=True, warm_up=STEPPING_WARM_UP)[0]
    worst = int(peaks.max())
    assert worst < one_view_peak, f"{part}: a tick's peak {worst} B, one view's {one_view_peak}"
    _, kept, numpy_kept = _run(parts[part], warm_up=STEPPING_WARM_UP)
    assert kept <= harness_kept, f"{part} kept {kept - harness_kept} B over {TICKS} ticks"
    assert numpy_kept == 0, f"{part} kept {numpy_kept} B of numpy data over {TICKS} ticks"
