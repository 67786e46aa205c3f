"""One validation walk compensated by Algorithm 1, Algorithm 2 or an offset, for the pipeline.

Each function simulates one walk and returns a :class:`CompensatedWalk`: the oscillation
metrics and the signals the figures need (trunk pitch, measured and target ZMP). They are
module-level so a process pool can run them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial

import numpy as np
from numpy.typing import NDArray

from zmpkit.compensate.algorithm1 import DEFAULT_ITERATIONS, compensate_abstraction
from zmpkit.compensate.algorithm2 import (
    Algorithm2Offsets,
    Algorithm2Parameters,
    OnlineZmpCompensator,
)
from zmpkit.compensate.evaluate import oscillation_of, simulate_with_offset
from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.compensate.offsets import OffsetParameters, offset_in_world
from zmpkit.errors import SimulationDivergedError
from zmpkit.experiments.walk import walk_controller
from zmpkit.experiments.walk_summary import WalkSummary, summarise_walk
from zmpkit.experiments.walk_trial import WalkRecord, simulate_walk
from zmpkit.walking import generate_pattern
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["CompensatedWalk", "walk_with_algorithm1", "walk_with_algorithm2", "walk_with_offset"]


@dataclass(frozen=True)
class CompensatedWalk:
    """One simulated walk with its compensation.

    Attributes:
        walk: the walk.
        step_peak_rad: trunk-pitch amplitude at the step frequency [rad].
        std_rad: trunk-pitch std over the steady walk [rad].
        fell: whether it fell (metrics penalised).
        time_s: [s], shape (N,).
        trunk_pitch_rad: [rad], shape (N,).
        window_s: the steady window [s].
        desired_zmp_in_world: the linear reference [m], shape (N, 2).
        target_zmp_in_world: the reference actually tracked, p' [m], shape (N, 2).
        measured_zmp_in_world: from the feet's F-T sensors [m], shape (N, 2).
        iteration_rms_m: Algorithm 1's RMS per iteration [m], empty otherwise.
    """

    walk: WalkSpec
    step_peak_rad: float
    std_rad: float
    fell: bool
    time_s: NDArray[np.float64]
    trunk_pitch_rad: NDArray[np.float64]
    window_s: tuple[float, float]
    desired_zmp_in_world: NDArray[np.float64]
    target_zmp_in_world: NDArray[np.float64]
    measured_zmp_in_world: NDArray[np.float64]
    iteration_rms_m: tuple[float, ...] = ()


def _result(
    walk: WalkSpec,
    pattern: WalkingPattern,
    record: WalkRecord | None,
    summary: WalkSummary | None,
    target: NDArray[np.float64],
    rms: Sequence[float] | NDArray[np.float64] = (),
) -> CompensatedWalk:
    """The compensated walk's outcome from its record (None: it diverged) and summary."""
    peak, std, fell = oscillation_of(summary)
    desired = pattern.linear_zmp_reference.zmp_in_world
    if record is None:
        empty = np.zeros(0)
        return CompensatedWalk(walk, peak, std, True, empty, empty, (0.0, 0.0), desired, target,
                               np.zeros((0, 2)), tuple(rms))  # fmt: skip
    assert summary is not None  # a record comes with its summary
    zmp = record.zmp_in_world()
    n = record.time_s.size
    return CompensatedWalk(
        walk, peak, std, fell, record.time_s, record.trunk_pitch_rad, summary.window_s,
        desired[:n], target[:n], zmp, tuple(float(r) for r in rms),
    )  # fmt: skip


def walk_with_offset(walk: WalkSpec, offset: OffsetParameters | None) -> CompensatedWalk:
    """``walk`` with ``offset`` on its reference (None: uncompensated)."""
    config = walk.walk_config()
    base = generate_pattern(config.pattern_config())
    zmp_offset = None if offset is None else offset_in_world(offset, base)
    outcome = simulate_with_offset(config, zmp_offset)
    target = outcome.pattern.zmp_reference_in_world
    return _result(walk, outcome.pattern, outcome.record, outcome.summary, target)


def walk_with_algorithm1(walk: WalkSpec, iterations: int = DEFAULT_ITERATIONS) -> CompensatedWalk:
    """``walk`` with Algorithm 1's offset, computed for this walk on the design model."""
    config = walk.walk_config()
    robot = config.robot
    compensation = compensate_abstraction(
        config.pattern_config(), robot.ik_model(), iterations, ik_settings=robot.ik_settings
    )
    outcome = simulate_with_offset(config, compensation.zmp_offset_in_world)
    target = outcome.pattern.zmp_reference_in_world
    return _result(walk, outcome.pattern, outcome.record, outcome.summary, target,
                   compensation.iteration_rms_m)  # fmt: skip


def walk_with_algorithm2(walk: WalkSpec, parameters: Algorithm2Parameters) -> CompensatedWalk:
    """``walk`` with Algorithm 2 running online on the measured ZMP.

    Open loop (``walk.controller`` ``open``): Algorithm 2's own preview controller plans the
    CoM on ``p'`` with no state feedback. With ``zmpip`` (paper B's line 3, "ZMP/IP-
    Controller(p')"): the feedback walk's observed preview control tracks ``p'``, which
    Algorithm 2 rewrites each frame from the F-T sensors' ZMP.
    """
    config = walk.walk_config()
    pattern = generate_pattern(config.pattern_config())
    robot = config.robot
    model, settings = robot.ik_model(), robot.ik_settings
    trajectory = solve_walking_ik(pattern, model, settings)
    sim = robot.make_simulation(config.effects, config.truth, seed=config.seed)
    learner: Algorithm2Offsets
    if config.controller == "open":
        hook = OnlineZmpCompensator(pattern, model, parameters, settings)
        learner = hook
        run = partial(simulate_walk, sim, trajectory, frame_hook=hook)
    else:
        learner = Algorithm2Offsets(pattern, parameters)
        controller = walk_controller(config, robot, pattern, trajectory, model, sim, learner.adapt)
        run = partial(simulate_walk, sim, trajectory, controller=controller)
    try:
        record = run()
    except SimulationDivergedError:
        return _result(walk, pattern, None, None, learner.target)
    summary = summarise_walk(pattern, trajectory, record, config.effects, config.seed)
    return _result(walk, pattern, record, summary, learner.target)
