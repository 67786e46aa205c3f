"""The ``zmpkit walk compensate`` pipeline: paper B §III.C and §III.E on the virtual NAO.

Methods: ``alg1`` (Algorithm 1, offline multibody-ZMP compensation on the design model),
``alg2`` (Algorithm 2, online on the measured ZMP), ``half-sine``, ``sawtooth``, ``fourier``
(periodic offsets tuned over simulated walks, :mod:`zmpkit.compensate.tuning`), and ``auto``
(tunes every shape, keeps the one with the lowest tuning objective). Every method is judged
on validation walks that tuning never saw (other noise seeds; 0.15 and 0.25 m/s), against the
same walks without compensation. "Peak" is the trunk-pitch spectrum's amplitude at the step
frequency; "std" the trunk pitch's standard deviation over the steady walk; the summary's
values are their means over the validation walks.

Writes ``summary.json`` (exactly :data:`SUMMARY_KEYS`, plus ``iteration_rms_m`` for
``alg1``), ``compensation.json`` (tuned parameters and tuning history), ``report.md`` and
the figures; tuning walks are cached under ``cache/`` (or ``cache_dir``) as they finish, so
a rerun resumes.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit import _validate
from zmpkit.compensate.algorithm1 import compensate_abstraction
from zmpkit.compensate.algorithm2 import Algorithm2Parameters
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
from zmpkit.errors import ParameterError
from zmpkit.experiments import MAX_WORKERS
from zmpkit.experiments.walk_config import STEP_DURATION_RANGE_S, max_walk_speed_mps
from zmpkit.robots.nao import nao_ik_model
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking import generate_pattern

__all__ = [
    "METHODS",
    "CompensateConfig",
    "CompensateProgress",
    "CompensateResult",
    "run_walk_compensate",
]

METHODS: tuple[str, ...] = ("alg1", "alg2", *OFFSET_SHAPES, "auto")
"""Values of ``--method``."""
QUICK_DURATION_S = 6.0
"""Walking time of every walk with ``--quick`` [s]."""
FULL_DURATION_S = 10.0
"""Walking time of every walk otherwise [s] (paper B's 10 s)."""
QUICK_EVALUATIONS, FULL_EVALUATIONS = 4, 16
"""Tuning candidates per shape after the prior, with and without ``--quick`` [-]."""
VALIDATION_SPEEDS_MPS = (0.15, 0.25)
"""Speeds of the validation walks besides the tuning speed [m/s]."""

CompensateProgress = Callable[[str, int, int], None]
"""``progress(stage, finished, total)``."""


@dataclass(frozen=True)
class CompensateConfig:
    """One ``zmpkit walk compensate`` run.

    Attributes:
        method: one of :data:`METHODS`.
        robot: robot name (``"nao"``).
        quick: short walks and a small tuning budget (< 5 min on 2 cores).
        speed_mps: speed of the tuning walk [m/s].
        step_duration_s: step duration [s] (the offsets' period).
        effects: effects of the virtual NAO (``"all"`` by default).
        seed: noise seed of the tuning walk; validation uses other seeds.
        workers: processes of the pool.
        iterations: iterations of Algorithm 1.
        bias_gain: α1 of Algorithm 2.
        smoothing_gain: α2 of Algorithm 2.
        evaluations: tuning candidates per shape, or None for the default of ``quick``.
        cache_dir: folder of cached walks, or None for ``OUT/cache``.
        figures: whether to draw the figures.
    """

    method: str = "auto"
    robot: str = "nao"
    quick: bool = False
    speed_mps: float = 0.2
    step_duration_s: float = 0.5
    effects: str = "all"
    seed: int = 0
    workers: int = 2
    iterations: int = 10
    bias_gain: float = 0.99
    smoothing_gain: float = 0.95
    evaluations: int | None = None
    cache_dir: str | None = None
    figures: bool = True

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ParameterError(f"method must be one of {', '.join(METHODS)}; got {self.method!r}")
        if self.robot != "nao":
            raise ParameterError(f"robot must be one of nao; got {self.robot!r}")
        _validate.in_range(
            "CompensateConfig.step_duration_s", self.step_duration_s, *STEP_DURATION_RANGE_S, "s"
        )
        fastest = round(max_walk_speed_mps(self.step_duration_s), 6)
        if not 0.0 < _validate.finite("CompensateConfig.speed_mps", self.speed_mps) <= fastest:
            raise ParameterError(
                f"CompensateConfig.speed_mps must lie in (0, {fastest:g}] m/s, "
                f"got {self.speed_mps:g} m/s"
            )
        if not 1 <= self.workers <= MAX_WORKERS:
            raise ParameterError(
                f"CompensateConfig.workers must lie in [1, {MAX_WORKERS}]; got {self.workers}"
            )
        for name in ("workers", "iterations"):
            if getattr(self, name) < 1:
                raise ParameterError(
                    f"CompensateConfig.{name} must be >= 1; got {getattr(self, name)}"
                )
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)
        self.algorithm2_parameters()

    @property
    def duration_s(self) -> float:
        """Walking time of every walk [s]."""
        return QUICK_DURATION_S if self.quick else FULL_DURATION_S

    @property
    def tuning_evaluations(self) -> int:
        """Tuning candidates per shape after the prior [-]."""
        if self.evaluations is not None:
            return self.evaluations
        return QUICK_EVALUATIONS if self.quick else FULL_EVALUATIONS

    def algorithm2_parameters(self) -> Algorithm2Parameters:
        """α1 and α2 of Algorithm 2."""
        return Algorithm2Parameters(self.bias_gain, self.smoothing_gain)

    def tuning_walks(self) -> tuple[WalkSpec, ...]:
        """The walk the offsets are tuned on."""
        return (WalkSpec(self.speed_mps, self.seed, self.duration_s, self.effects),)

    def validation_walks(self) -> tuple[WalkSpec, ...]:
        """Walks never used for tuning: other seeds at the tuning speed, and other speeds."""
        d, e, s = self.duration_s, self.effects, self.seed
        other = [WalkSpec(v, s + 1, d, e) for v in VALIDATION_SPEEDS_MPS]
        if self.quick:
            return tuple(other)
        return (WalkSpec(self.speed_mps, s + 1, d, e), WalkSpec(self.speed_mps, s + 2, d, e),
                *other)  # fmt: skip


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
            :func:`~zmpkit.pipelines.walk_compensate_report.write_walk_compensate`).
    """

    config: CompensateConfig
    summary: CompensationSummary
    chosen: str
    baseline: tuple[CompensatedWalk, ...]
    compensated: dict[str, tuple[CompensatedWalk, ...]]
    tuning: dict[str, TuningResult] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)


def _pool_map(jobs: list[tuple[Callable, tuple]], workers: int) -> list[CompensatedWalk]:
    if workers <= 1:
        return [function(*args) for function, args in jobs]
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(function, *args) for function, args in jobs]
        return [f.result() for f in futures]


def _tune_shapes(config: CompensateConfig, cache: Path, report) -> dict[str, TuningResult]:
    shapes = OFFSET_SHAPES if config.method == "auto" else (config.method,)
    walk = config.tuning_walks()[0].walk_config()
    pattern = generate_pattern(walk.pattern_config())
    model_offset = compensate_abstraction(walk.pattern_config(), nao_ik_model(), config.iterations)
    results = {}
    for i, shape in enumerate(shapes):
        report(f"tuning {shape}", i, len(shapes))
        prior = prior_from_offset(shape, model_offset.zmp_offset_in_world, pattern)
        results[shape] = tune_offset(prior, config.tuning_walks(), config.tuning_evaluations,
                                     cache, config.workers, config.seed)  # fmt: skip
    return results


def _validation_jobs(config: CompensateConfig, offsets: dict[str, OffsetParameters]):
    walks = config.validation_walks()
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
    """Compensate the virtual NAO's walk with ``config.method``.

    Tuning walks are cached under ``out_dir/cache`` (or ``config.cache_dir``) as they finish,
    so a rerun resumes; the results are written by
    :func:`~zmpkit.pipelines.walk_compensate_report.write_walk_compensate`.

    Args:
        config: the run.
        out_dir: output folder of the run (created if missing).
        progress: called with (stage, finished, total) as stages finish.

    Returns:
        The summary, the validation walks and the tuning.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cache = Path(config.cache_dir) if config.cache_dir else out / "cache"
    report = progress or (lambda stage, done, total: None)
    tuning = (
        _tune_shapes(config, cache, report) if config.method in (*OFFSET_SHAPES, "auto") else {}
    )
    offsets = {shape: result.best for shape, result in tuning.items()}
    jobs, labels = _validation_jobs(config, offsets)
    report("validation walks", 0, len(jobs))
    walks = _pool_map(jobs, config.workers)
    report("validation walks", len(jobs), len(jobs))
    n = len(config.validation_walks())
    baseline = tuple(walks[:n])
    compensated = {label: tuple(walks[n * (i + 1) : n * (i + 2)]) for i, label in enumerate(labels)}
    chosen = min(tuning, key=lambda s: tuning[s].best_objective) if tuning else labels[0]
    summary = summary_of(config.method, baseline, compensated[chosen])
    return CompensateResult(config, summary, chosen, baseline, compensated, tuning)
