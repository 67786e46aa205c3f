r"""Automatic tuning of the ZMP offsets over simulated walks (paper B tuned the phase by hand).

Objective of an offset ``o`` on the tuning walks ``W`` (all effects on), each normalised by
the same walk without offset:

.. math::

    J(o) = \frac{1}{|W|}\sum_{w \in W}
        \frac{A_{f_s}(w, o)}{A_{f_s}(w, 0)} + \frac{\sigma(w, o)}{\sigma(w, 0)},

``A_{f_s}`` the trunk-pitch spectrum's amplitude at the step frequency and ``σ`` the trunk
pitch's standard deviation over the steady walk (``J = 2`` means no change); a fall counts
as :data:`~zmpkit.compensate.evaluate.FALL_PENALTY_RAD`.

Search: CMA-ES (``cma``) on scaled parameters — (amplitude / :data:`SCALE_M`,
phase / :data:`PHASE_SCALE`) for the half sine and the sawtooth, the coefficients /
:data:`SCALE_M` for the Fourier offset. It
starts from a model-based guess: the least-squares fit of the shape to the walking-direction
part of Algorithm 1's offset on the design model (:func:`prior_from_offset`), which needs no
measurement of the robot. Evaluations run in a process pool and are cached
(:mod:`zmpkit.compensate.evaluations`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cma
import numpy as np
from numpy.typing import NDArray

from zmpkit.compensate.evaluations import DEFAULT_WORKERS, Evaluation, WalkSpec, evaluate_all
from zmpkit.compensate.offsets import OffsetParameters, periodic_wave
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["SCALE_M", "TuningResult", "objective", "prior_from_offset", "tune_offset"]

SCALE_M = 0.01
"""Scale of amplitudes and coefficients in the search space [m]."""
INITIAL_SIGMA = 0.3
"""CMA-ES initial step size, in scaled units [-]."""
PHASE_SCALE = 0.05
"""Scale of the phase in the search space [step]."""
PHASE_GRID = 40
"""Phases tried when fitting a half sine or sawtooth to an offset [-]."""


@dataclass(frozen=True)
class TuningResult:
    """The outcome of tuning one shape.

    Attributes:
        shape: the offset shape.
        prior: the model-based start.
        best: the offset with the lowest objective.
        best_objective: its J [-].
        history: (offset, J) of every evaluated candidate, in order.
        baseline: the uncompensated tuning walks.
    """

    shape: str
    prior: OffsetParameters
    best: OffsetParameters
    best_objective: float
    history: tuple[tuple[OffsetParameters, float], ...]
    baseline: tuple[Evaluation, ...]


def objective(evaluations: Sequence[Evaluation], baseline: Sequence[Evaluation]) -> float:
    """J of one offset over the tuning walks (module docstring) [-]."""
    terms = [
        e.step_peak_rad / b.step_peak_rad + e.std_rad / b.std_rad
        for e, b in zip(evaluations, baseline, strict=True)
    ]
    return float(np.mean(terms))


def _fit_design(
    shape: str, u: NDArray[np.float64], phase: float, harmonics: int
) -> NDArray[np.float64]:
    """The least-squares design matrix of ``shape`` at the step phases ``u`` [-]."""
    if shape == "fourier":
        cols = []
        for k in range(1, harmonics + 1):
            cols += [np.cos(2 * np.pi * k * u), np.sin(2 * np.pi * k * u)]
        return np.column_stack([*cols, np.ones_like(u)])
    unit = OffsetParameters(shape, 1.0, phase)
    return np.column_stack([periodic_wave(unit, u, 1.0), np.ones_like(u)])


def prior_from_offset(
    shape: str, offset_in_world: NDArray[np.float64], pattern: WalkingPattern, harmonics: int = 2
) -> OffsetParameters:
    """Least-squares fit of ``shape`` (plus a constant) to the x part of an offset [m].

    Fitted over the steady walk (two steps after the start to two before the end); the
    result scales with speed from ``pattern``'s speed on.
    """
    plan = pattern.footsteps
    step_s, start_s = plan.gait.step_duration_s, plan.walk_start_s
    t = pattern.time_s
    steady = (t >= start_s + 2 * step_s) & (t <= plan.steps[-1].t_end - 2 * step_s)
    u, x = (t[steady] - start_s) / step_s, offset_in_world[steady, 0]
    speed = abs(pattern.config.command.v_x)
    if shape == "fourier":
        coef = np.linalg.lstsq(_fit_design(shape, u, 0.0, harmonics), x, rcond=None)[0]
        coefficients = tuple(float(c) for c in coef[:-1])
        return OffsetParameters("fourier", fourier_m=coefficients, reference_speed_mps=speed)
    best = (np.inf, 0.0, 0.0)
    for phase in np.arange(PHASE_GRID) / PHASE_GRID:
        design = _fit_design(shape, u, phase, harmonics)
        coef, residual = np.linalg.lstsq(design, x, rcond=None)[:2]
        cost = float(residual[0]) if residual.size else float(np.sum((design @ coef - x) ** 2))
        best = min(best, (cost, float(coef[0]), float(phase)))
    return OffsetParameters(shape, best[1], best[2], reference_speed_mps=speed)


def _encode(p: OffsetParameters) -> NDArray[np.float64]:
    if p.shape == "fourier":
        return np.asarray(p.fourier_m) / SCALE_M
    return np.array([p.amplitude_m / SCALE_M, p.phase / PHASE_SCALE])


def _decode(prior: OffsetParameters, x: NDArray[np.float64]) -> OffsetParameters:
    speed = prior.reference_speed_mps
    if prior.shape == "fourier":
        coefficients = tuple(float(v) * SCALE_M for v in x)
        return OffsetParameters("fourier", fourier_m=coefficients, reference_speed_mps=speed)
    amplitude, phase = float(x[0]) * SCALE_M, float(x[1]) * PHASE_SCALE % 1.0
    return OffsetParameters(prior.shape, amplitude, phase, reference_speed_mps=speed)


def tune_offset(
    prior: OffsetParameters,
    walks: Sequence[WalkSpec],
    evaluations: int,
    cache_dir: Path | None = None,
    workers: int = DEFAULT_WORKERS,
    seed: int = 0,
) -> TuningResult:
    """Tune ``prior``'s shape by CMA-ES from ``prior`` within ``evaluations`` candidates.

    Args:
        prior: the start (its shape is tuned).
        walks: the tuning walks.
        evaluations: candidates evaluated after the prior, rounded up to whole generations
            of ``workers`` (at least 2 per generation).
        cache_dir: cache of walks (see :mod:`zmpkit.compensate.evaluations`).
        workers: processes.
        seed: seed of CMA-ES.
    """
    baseline = tuple(evaluate_all([(w, None) for w in walks], cache_dir, workers))
    history = [(prior, _score(prior, walks, baseline, cache_dir, workers))]
    popsize = max(2, workers)
    options = {"popsize": popsize, "seed": seed + 1, "verbose": -9}
    strategy = cma.CMAEvolutionStrategy(_encode(prior), INITIAL_SIGMA, options)
    while len(history) - 1 < evaluations:
        xs = strategy.ask()
        candidates = [_decode(prior, np.asarray(x)) for x in xs]
        scores = _scores(candidates, walks, baseline, cache_dir, workers)
        strategy.tell(xs, scores)
        history += list(zip(candidates, scores, strict=True))
    best, score = min(history, key=lambda item: item[1])
    return TuningResult(prior.shape, prior, best, score, tuple(history), baseline)


def _score(
    offset: OffsetParameters,
    walks: Sequence[WalkSpec],
    baseline: Sequence[Evaluation],
    cache_dir: Path | None,
    workers: int,
) -> float:
    """J of ``offset`` over ``walks`` (:func:`objective`)."""
    return _scores([offset], walks, baseline, cache_dir, workers)[0]


def _scores(
    offsets: Sequence[OffsetParameters],
    walks: Sequence[WalkSpec],
    baseline: Sequence[Evaluation],
    cache_dir: Path | None,
    workers: int,
) -> list[float]:
    """J of each of ``offsets`` over ``walks``, all evaluated together."""
    tasks = [(w, o) for o in offsets for w in walks]
    results = evaluate_all(tasks, cache_dir, workers)
    n = len(walks)
    return [objective(results[i * n : (i + 1) * n], baseline) for i in range(len(offsets))]
