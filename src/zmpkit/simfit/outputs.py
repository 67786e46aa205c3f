"""Files a simulator fit writes into its output folder (besides the checkpoint).

- :data:`FITTED_TRUTH_FILE`: the base truth with the fitted values — a truth file the
  simulator loads as ``--truth``;
- :data:`FITTED_PARAMETERS_FILE`: per parameter its value, unit, nominal, bounds, path in the
  truth file and identifiability;
- :data:`HISTORY_CSV`: one row per generation (costs, step size, its IPOP restart and
  population, best-so-far values);
- :data:`IDENTIFIABILITY_FILE`: the cost profile, the marginal resolution and the CMA-ES
  spread per parameter;
- :data:`SLOPPY_DIRECTIONS_FILE`: the combinations of parameters the data leave loose
  (:mod:`~zmpkit.simfit.cost_hessian`), one row each, loosest first (header only if none);
- :data:`INTERVALS_FILE`: per parameter its 95 % interval, its centre, the estimator's
  bias it corrects, and which interval it is (:mod:`~zmpkit.simfit.refit_intervals`);
- :data:`REPRODUCTION_FILE`: per fitted and held-out experiment, trunk-oscillation frequency
  and amplitude recorded vs simulated and the joint-angle RMS error.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import yaml

from zmpkit.simfit.adequacy import Adequacy
from zmpkit.simfit.checkpoint import GenerationRecord
from zmpkit.simfit.cost_hessian import CostDirection
from zmpkit.simfit.identifiability import ParameterIdentifiability
from zmpkit.simfit.parameters import FitParameter, ParameterValues
from zmpkit.simfit.refit_intervals import ParameterInterval
from zmpkit.simfit.truth_doc import truth_doc_with, write_truth_doc
from zmpkit.simfit.validation import ReproductionCheck

__all__ = [
    "FITTED_PARAMETERS_FILE",
    "FITTED_TRUTH_FILE",
    "HISTORY_CSV",
    "IDENTIFIABILITY_FILE",
    "INTERVALS_FILE",
    "REPRODUCTION_FILE",
    "SLOPPY_DIRECTIONS_FILE",
    "adequacy_entry",
    "write_fitted_parameters",
    "write_fitted_truth",
    "write_history_csv",
    "write_identifiability_csv",
    "write_intervals_csv",
    "write_reproduction_csv",
    "write_sloppy_directions_csv",
]

FITTED_TRUTH_FILE = "fitted_truth.yaml"
FITTED_PARAMETERS_FILE = "fitted_parameters.yaml"
HISTORY_CSV = "cost_history.csv"
IDENTIFIABILITY_FILE = "identifiability.csv"
INTERVALS_FILE = "intervals.csv"
REPRODUCTION_FILE = "reproduction.csv"
SLOPPY_DIRECTIONS_FILE = "sloppy_directions.csv"


def _csv(path: Path, header: Sequence[str], rows: Sequence[Sequence[object]]) -> Path:
    def cell(v: object) -> str:
        if isinstance(v, bool):
            return str(v).lower()
        if isinstance(v, float | np.floating):
            return "" if not np.isfinite(v) else f"{float(v):.8g}"
        return str(v)

    lines = [",".join(header)] + [",".join(cell(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def write_fitted_truth(
    path: Path,
    base_doc: dict,
    parameters: Sequence[FitParameter],
    values: ParameterValues,
    source: str,
) -> Path:
    """The base truth with the fitted values, loadable as ``--truth``."""
    header = f"Truth fitted by 'zmpkit identify sim' (CMA-ES) from {source}.\nFitted: " + ", ".join(
        f"{p.path} = {v:.6g} {p.unit}" for p, v in zip(parameters, values, strict=True)
    )
    return write_truth_doc(truth_doc_with(base_doc, parameters, values), path, header)


def _pct_or_none(fraction: float) -> float | None:
    return None if not np.isfinite(fraction) else 100 * float(fraction)


def _finite_or_none(value: float) -> float | None:
    return None if not np.isfinite(value) else value


def write_fitted_parameters(
    path: Path,
    robot: str,
    effects: str,
    cost: float,
    parameters: Sequence[FitParameter],
    ident: Sequence[ParameterIdentifiability],
    adequacy: Adequacy | None = None,
    intervals: Sequence[ParameterInterval] = (),
) -> Path:
    """Per parameter: value, unit, nominal, bounds, truth path, identifiability.

    With ``intervals``, per parameter ``interval_95`` (``[lower, upper]`` [unit], None when
    not measured), ``interval_95_half_width_pct``, ``interval_95_centre`` [unit] (the
    bias-corrected estimate), ``estimator_bias_pct`` (None when not estimated) and
    ``interval_95_method`` (which interval it is and what it covers), and for a
    bias-corrected one ``replica_moves_pct``, each re-fitted replica's move [%].

    With ``adequacy``, the check's numbers and verdict (key ``adequacy``), and per parameter
    ``resolution_is_precision``: false when the model does not explain the data (then the
    resolutions say how the misfit moves, not how precisely the value is known).
    """
    precision = None if adequacy is None else adequacy.explains is not False
    by_name = {i.name: i for i in intervals}
    entries = {
        p.name: {
            "value": float(i.value),
            "unit": p.unit,
            "nominal": p.nominal,
            "bounds": [p.lower, p.upper],
            "path": p.path,
            "effect": p.effect,
            "identifiable": bool(i.identifiable),
            "identifiable_why": i.reason,
            "resolution_pct": None if not np.isfinite(i.resolution) else 100 * i.resolution,
            "marginal_resolution_pct": _pct_or_none(i.marginal_resolution),
            "cma_relative_std": _finite_or_none(float(i.cma_relative_std)),
        }
        | ({} if precision is None else {"resolution_is_precision": precision})
        | _interval_entry(by_name.get(p.name))
        for p, i in zip(parameters, ident, strict=True)
    }
    doc = {"robot": robot, "effects": effects, "cost": float(cost), "parameters": entries}
    if adequacy is not None:
        doc["adequacy"] = adequacy_entry(adequacy)
    path.write_text(yaml.safe_dump(doc, sort_keys=False, allow_unicode=True), encoding="utf-8")
    return path


def _interval_entry(interval: ParameterInterval | None) -> dict:
    if interval is None:
        return {}
    measured = math.isfinite(interval.half_width)
    return {
        "interval_95": [interval.lower, interval.upper] if measured else None,
        "interval_95_half_width_pct": 100 * interval.half_width if measured else None,
        "interval_95_centre": _number(interval.corrected),
        "estimator_bias_pct": _pct_or_none(interval.bias),
        "interval_95_method": interval.method,
    } | ({"replica_moves_pct": [100 * m for m in interval.moves]} if interval.moves else {})


def _number(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def adequacy_entry(adequacy: Adequacy) -> dict:
    """The model-adequacy check as plain data (numbers; None where undefined)."""
    return {
        "explains_data": adequacy.explains,
        "verdict": adequacy.verdict,
        "best_cost": _number(adequacy.best_cost),
        "noise_floor": _number(adequacy.noise_floor),
        "noise_floor_std": _number(adequacy.floor_std),
        "cost_to_floor_ratio": _number(adequacy.ratio),
        "explained_up_to": _number(adequacy.limit),
        "replicas": adequacy.replicas,
        "residual_lag1": _number(adequacy.residual_lag1),
        "noise_floor_residual_lag1": _number(adequacy.floor_residual_lag1),
        "noise_floor_residual_lag1_std": _number(adequacy.floor_residual_lag1_std),
        "residual_lag1_limit": _number(adequacy.lag1_limit),
        "residuals_structured": adequacy.structured,
    }


def write_history_csv(
    path: Path, history: Sequence[GenerationRecord], parameters: Sequence[FitParameter]
) -> Path:
    """One row per generation: costs [-], step [-], time [s], restart, population, values."""
    header = [
        "generation",
        "evaluations",
        "best_cost",
        "best_so_far",
        "median_cost",
        "sigma",
        "wall_s",
        "restart",
        "popsize",
        *(p.name for p in parameters),
    ]
    rows = [
        [
            r.generation,
            r.evaluations,
            r.best_cost,
            r.best_so_far,
            r.median_cost,
            r.sigma,
            r.wall_s,
            r.restart,
            r.popsize,
            *(r.best_values[p.name] for p in parameters),
        ]
        for r in history
    ]
    return _csv(path, header, rows)


def write_identifiability_csv(path: Path, ident: Sequence[ParameterIdentifiability]) -> Path:
    """Per parameter: profile costs, resolution, CMA-ES spread, verdict, marginal resolution.

    Resolutions and spread in %; an empty cell: no visible rise within ±100 %.
    """
    header = [
        "parameter",
        "value",
        "cost_minus",
        "cost_opt",
        "cost_plus",
        "resolution_pct",
        "cma_relative_std_pct",
        "identifiable",
        "marginal_resolution_pct",
    ]
    rows = [
        [
            i.name,
            i.value,
            i.cost_minus,
            i.cost_opt,
            i.cost_plus,
            100 * i.resolution,
            100 * i.cma_relative_std,
            str(bool(i.identifiable)).lower(),  # as in recovery.csv
            100 * i.marginal_resolution,
        ]
        for i in ident
    ]
    return _csv(path, header, rows)


def write_intervals_csv(path: Path, intervals: Sequence[ParameterInterval]) -> Path:
    """Per parameter: fitted value, 95 % interval, its centre, bias and half-width [%], kind.

    The kind is ``pipeline_refits``, ``window_refits`` or ``noise_only``; the
    ``interval_95_method`` of :data:`FITTED_PARAMETERS_FILE` says it in words. An empty
    cell: not measured (or, for the bias, not estimated: a noise-only interval).
    """
    header = [
        "parameter",
        "value",
        "lower",
        "upper",
        "centre",
        "estimator_bias_pct",
        "half_width_pct",
        "replicas",
        "kind",
    ]
    rows = [
        [
            i.name,
            i.value,
            i.lower,
            i.upper,
            i.corrected,
            100 * i.bias,
            100 * i.half_width,
            i.replicas,
            i.kind,
        ]
        for i in intervals
    ]
    return _csv(path, header, rows)


def write_sloppy_directions_csv(path: Path, directions: Sequence[CostDirection]) -> Path:
    """One row per loose direction: resolution [%], curvature [-], main components.

    An empty resolution: no visible rise within ±100 %; components as ``name:+0.710 …``.
    """
    header = ["direction", "resolution_pct", "curvature", "components"]
    rows = [
        [
            k + 1,
            100 * d.resolution,
            d.curvature,
            " ".join(f"{name}:{value:+.3f}" for name, value in d.components),
        ]
        for k, d in enumerate(directions)
    ]
    return _csv(path, header, rows)


def write_reproduction_csv(
    path: Path, fitted: Sequence[ReproductionCheck], held_out: Sequence[ReproductionCheck]
) -> Path:
    """Trunk oscillation and joint-angle error per experiment, fitted and held out."""
    header = [
        "experiment",
        "set",
        "recorded_peak_hz",
        "simulated_peak_hz",
        "frequency_error_hz",
        "recorded_amplitude_rad",
        "simulated_amplitude_rad",
        "amplitude_error_pct",
        "joint_rms_error_rad",
        "resolution_hz",
        "passed",
    ]
    rows = [
        [
            c.experiment,
            label,
            c.recorded_peak_hz,
            c.simulated_peak_hz,
            c.frequency_error_hz,
            c.recorded_amplitude_rad,
            c.simulated_amplitude_rad,
            100 * c.amplitude_error,
            c.joint_rms_error_rad,
            c.resolution_hz,
            c.passed,
        ]
        for label, checks in (("fit", fitted), ("held_out", held_out))
        for c in checks
    ]
    return _csv(path, header, rows)
