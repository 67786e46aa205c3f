"""The ``zmpkit walk compensate`` pipeline: paper B §III.C and §III.E on a walking robot.

Methods: ``alg1`` (Algorithm 1, offline multibody-ZMP compensation on the design model),
``alg2`` (Algorithm 2, online on the measured ZMP; with ``zmpip`` it rewrites the reference of
the feedback walk's observed preview control, paper B's line 3), ``half-sine``, ``sawtooth``,
``fourier`` (periodic offsets tuned over simulated walks, :mod:`zmpkit.compensate.tuning`), and
``auto`` (tunes every shape, keeps the one with the lowest tuning objective). Every method is
judged on validation walks that tuning never saw, against the same walks without compensation:
open loop (paper B's simulation), other noise seeds and 0.15 and 0.25 m/s; with feedback
(``controller`` ``zmpip`` or ``dcm``, as paper B's robot walks), tuning scores each candidate
on walks at two speeds and two step durations (a fall is a failure), and every validation walk
differs from all of them in speed, step duration and robot (gear stiffness ±15–30 %,
:data:`~zmpkit.pipelines.walk_compensate_config.HELD_OUT_WALKS`). A compensation that makes a
validation walk fall that stands without it is rejected (``rejected`` in ``summary.json``, and
the report says so). "Peak" is the trunk-pitch spectrum's amplitude at the step frequency;
"std" the trunk pitch's standard deviation over the steady walk; the summary's values are their
means over the validation walks.

The walks were designed for paper B's robot at its 0.2 m/s
(:data:`~zmpkit.robots.robot.DEFAULT_WALK_SPEED_MPS`); on another robot every speed and speed
change above is scaled by the robot's walking speed over 0.2 m/s
(:attr:`~zmpkit.pipelines.walk_compensate_config.CompensateConfig.speed_scale`: 0.5 for a robot
that walks at 0.1 m/s; step durations are kept), and the tuning speed is the robot's walking
speed unless one is given.

Writes ``summary.json`` (exactly :data:`SUMMARY_KEYS`, plus ``iteration_rms_m`` for
``alg1``), ``compensation.json`` (tuned parameters and tuning history), ``report.html`` and
the figures; tuning walks are cached under ``cache/`` (or ``cache_dir``) as they finish, so
a rerun resumes.
"""

from __future__ import annotations

import multiprocessing
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit.compensate.algorithm1 import compensate_abstraction
from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.compensate.methods import (
    CompensatedWalk,
    walk_with_algorithm1,
    walk_with_algorithm2,
    walk_with_offset,
)
from zmpkit.compensate.offsets import OFFSET_SHAPES, OffsetParameters
from zmpkit.compensate.summary import CompensationSummary, summary_of
from zmpkit.compensate.tuning import TuningResult, prior_from_offset, tune_offset
from zmpkit.pipelines.walk_compensate_config import METHODS, CompensateConfig
from zmpkit.walking import generate_pattern

__all__ = [
    "METHODS",
    "CompensateConfig",
    "CompensateProgress",
    "CompensateResult",
    "run_walk_compensate",
]


CompensateProgress = Callable[[str, int, int], None]
"""``progress(stage, finished, total)``."""


@dataclass(frozen=True)
class CompensateResult:
    """What a compensation run produced.

    Attributes:
        config: what was asked.
        summary: what ``summary.json`` holds.
        chosen: the method or shape whose numbers the summary reports.
        baseline: the validation walks without compensation.
        compensated: method or shape -> its validation walks.
        tuning: shape -> tuning result (offset methods only).
        files: every file written, by role (empty until
            :func:`~zmpkit.pipelines.walk_compensate_files.write_walk_compensate`).
        started_s: when the run started [s since the epoch].
    """

    config: CompensateConfig
    summary: CompensationSummary
    chosen: str
    baseline: tuple[CompensatedWalk, ...]
    compensated: dict[str, tuple[CompensatedWalk, ...]]
    tuning: dict[str, TuningResult] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)


def _pool_map(jobs: list[tuple[Callable, tuple]], workers: int) -> list[CompensatedWalk]:
    if workers <= 1:
        return [function(*args) for function, args in jobs]
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(function, *args) for function, args in jobs]
        return [f.result() for f in futures]


def _tune_shapes(
    config: CompensateConfig, cache: Path, report: Callable[[str, int, int], None]
) -> dict[str, TuningResult]:
    shapes = OFFSET_SHAPES if config.method == "auto" else (config.method,)
    walk = config.tuning_walks()[0].walk_config()
    pattern = generate_pattern(walk.pattern_config())
    robot = config.robot
    model_offset = compensate_abstraction(
        walk.pattern_config(), robot.ik_model(), config.iterations, ik_settings=robot.ik_settings
    )
    results = {}
    for i, shape in enumerate(shapes):
        report(f"tuning {shape}", i, len(shapes))
        prior = prior_from_offset(shape, model_offset.zmp_offset_in_world, pattern)
        results[shape] = tune_offset(prior, config.tuning_walks(), config.tuning_evaluations,
                                     cache, config.workers, config.seed)  # fmt: skip
    return results


def _validation_jobs(
    config: CompensateConfig, offsets: dict[str, OffsetParameters], walks: tuple[WalkSpec, ...]
) -> tuple[list[tuple[Callable, tuple]], list[str]]:
    jobs: list[tuple[Callable, tuple]] = [(walk_with_offset, (w, None)) for w in walks]
    if config.method == "alg1":
        jobs += [(walk_with_algorithm1, (w, config.iterations)) for w in walks]
        return jobs, ["alg1"]
    if config.method == "alg2":
        jobs += [(walk_with_algorithm2, (w, config.algorithm2_parameters())) for w in walks]
        return jobs, ["alg2"]
    for offset in offsets.values():
        jobs += [(walk_with_offset, (w, offset)) for w in walks]
    return jobs, list(offsets)


def run_walk_compensate(
    config: CompensateConfig, out_dir: str | Path, progress: CompensateProgress | None = None
) -> CompensateResult:
    """Compensate the walking robot's walk with ``config.method``.

    Tuning walks are cached under ``out_dir/cache`` (or ``config.cache_dir``) as they finish,
    so a rerun resumes; the results are written by
    :func:`~zmpkit.pipelines.walk_compensate_files.write_walk_compensate`.

    Args:
        config: the run.
        out_dir: output folder of the run (created if missing).
        progress: called with (stage, finished, total) as stages finish.

    Returns:
        The summary, the validation walks and the tuning.
    """
    started_s = time.time()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cache = Path(config.cache_dir) if config.cache_dir else out / "cache"
    report = progress or (lambda stage, done, total: None)
    tuning = (
        _tune_shapes(config, cache, report) if config.method in (*OFFSET_SHAPES, "auto") else {}
    )
    offsets = {shape: result.best for shape, result in tuning.items()}
    walks_out = config.validation_walks(cache / "held_out_robots")
    jobs, labels = _validation_jobs(config, offsets, walks_out)
    report("validation walks", 0, len(jobs))
    walks = _pool_map(jobs, config.workers)
    report("validation walks", len(jobs), len(jobs))
    n = len(walks_out)
    baseline = tuple(walks[:n])
    compensated = {label: tuple(walks[n * (i + 1) : n * (i + 2)]) for i, label in enumerate(labels)}
    chosen = min(tuning, key=lambda s: tuning[s].best_objective) if tuning else labels[0]
    summary = summary_of(config.method, baseline, compensated[chosen])
    return CompensateResult(
        config, summary, chosen, baseline, compensated, tuning, started_s=started_s
    )
