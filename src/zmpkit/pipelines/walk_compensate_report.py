"""``summary.json``, ``compensation.json``, ``report.md`` and the figures of a compensation run.

The summary's contract is :data:`SUMMARY_KEYS` (plus ``iteration_rms_m`` for ``alg1``):
means over the validation walks of the step-frequency amplitude and the std of the trunk
pitch, without and with the compensation, their reductions [%], and one entry per walk.
Walks whose uncompensated version fell are listed but left out of the means.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from zmpkit.analysis.walk_metrics import amplitude_spectrum
from zmpkit.compensate.methods import CompensatedWalk

if TYPE_CHECKING:
    from zmpkit.pipelines.walk_compensate import CompensateResult

__all__ = [
    "EXTRA_SUMMARY_KEYS",
    "REPORT_FILE",
    "SUMMARY_FILE",
    "SUMMARY_KEYS",
    "summary_of",
    "write_outputs",
]

SUMMARY_FILE = "summary.json"
REPORT_FILE = "report.md"
DETAILS_FILE = "compensation.json"
SUMMARY_KEYS: tuple[str, ...] = (
    "method", "baseline_peak_amplitude_rad", "compensated_peak_amplitude_rad",
    "peak_reduction_pct", "baseline_std_rad", "compensated_std_rad", "std_reduction_pct",
    "validation_walks",
)  # fmt: skip
"""Keys of ``summary.json`` (``alg1`` adds ``iteration_rms_m``)."""
EXTRA_SUMMARY_KEYS = ("walks_compared", "compensated_falls")
"""Keys zmpkit adds: how many validation walks the means cover (neither version fell), and
how many compensated walks fell."""


def _reduction(before: float | None, after: float | None) -> float | None:
    """100·(1 − after/before) [%]; None when either walk has no oscillation to compare."""
    if before is None or after is None or before == 0.0:
        return None
    return float(100.0 * (1.0 - after / before))


def _peak(walk: CompensatedWalk) -> float | None:
    """Step-frequency peak [rad]; None for a walk that fell (it has no steady oscillation)."""
    return None if walk.fell else walk.step_peak_rad


def _std(walk: CompensatedWalk) -> float | None:
    """Trunk-pitch std [rad]; None for a walk that fell."""
    return None if walk.fell else walk.std_rad


def _walk_entry(base: CompensatedWalk, comp: CompensatedWalk) -> dict[str, object]:
    w = base.walk
    return {
        "speed_mps": w.speed_mps, "seed": w.seed, "duration_s": w.duration_s,
        "baseline_peak_amplitude_rad": _peak(base),
        "compensated_peak_amplitude_rad": _peak(comp),
        "peak_reduction_pct": _reduction(_peak(base), _peak(comp)),
        "baseline_std_rad": _std(base), "compensated_std_rad": _std(comp),
        "std_reduction_pct": _reduction(_std(base), _std(comp)),
        "baseline_fell": base.fell, "compensated_fell": comp.fell,
    }  # fmt: skip


def _mean(values: list[float | None]) -> float | None:
    kept = [v for v in values if v is not None]
    return float(np.mean(kept)) if kept else None


def summary_of(
    method: str, baseline: Sequence[CompensatedWalk], compensated: Sequence[CompensatedWalk]
) -> dict[str, object]:
    """The ``summary.json`` dictionary (module docstring).

    The means are over the validation walks where neither the uncompensated nor the
    compensated walk fell (``walks_compared``); a fall is never turned into a number.
    ``compensated_falls`` counts compensated walks that fell, so a compensation that makes
    the robot fall cannot hide behind the means.
    """
    pairs = [(b, c) for b, c in zip(baseline, compensated, strict=True)]
    both = [(b, c) for b, c in pairs if not b.fell and not c.fell]
    peaks = [_mean([_peak(w[k]) for w in both]) for k in (0, 1)]
    stds = [_mean([_std(w[k]) for w in both]) for k in (0, 1)]
    summary: dict[str, object] = {
        "method": method,
        "baseline_peak_amplitude_rad": peaks[0],
        "compensated_peak_amplitude_rad": peaks[1],
        "peak_reduction_pct": _reduction(*peaks),
        "baseline_std_rad": stds[0],
        "compensated_std_rad": stds[1],
        "std_reduction_pct": _reduction(*stds),
        "validation_walks": [_walk_entry(b, c) for b, c in pairs],
        EXTRA_SUMMARY_KEYS[0]: len(both),
        EXTRA_SUMMARY_KEYS[1]: sum(c.fell for _, c in pairs),
    }
    if method == "alg1":
        summary["iteration_rms_m"] = list(compensated[0].iteration_rms_m)
    return summary


def _details(result: CompensateResult) -> dict[str, object]:
    tuning = {
        shape: {
            "prior": t.prior.as_dict(), "best": t.best.as_dict(),
            "best_objective": t.best_objective,
            "history": [{"offset": o.as_dict(), "objective": j} for o, j in t.history],
        }
        for shape, t in result.tuning.items()
    }  # fmt: skip
    validation = {
        label: [_walk_entry(b, c) for b, c in zip(result.baseline, walks, strict=True)]
        for label, walks in result.compensated.items()
    }
    return {"chosen": result.chosen, "tuning": tuning, "validation": validation}


def _cell(value: object, digits: int, fell: bool = False) -> str:
    if fell:
        return "fell"
    return "–" if value is None else f"{value:.{digits}f}"


def _report(result: CompensateResult, figures: dict[str, Path]) -> str:
    s = result.summary
    lines = [
        f"## Walking compensation: `{s['method']}` (reported: {result.chosen})", "",
        f"Virtual NAO, effects {result.config.effects}; validation walks not used for tuning.",
        "Peak = trunk-pitch spectrum amplitude at the step frequency; std over the steady walk.",
        "", "| walk | peak before [rad] | peak after [rad] | peak cut [%] | std before [rad] "
        "| std after [rad] | std cut [%] |", "|---|---|---|---|---|---|---|",
    ]  # fmt: skip
    for w in s["validation_walks"]:  # type: ignore[union-attr]
        lines.append(
            f"| {w['speed_mps']:g} m/s seed {w['seed']} "
            f"| {_cell(w['baseline_peak_amplitude_rad'], 4, w['baseline_fell'])} "
            f"| {_cell(w['compensated_peak_amplitude_rad'], 4, w['compensated_fell'])} "
            f"| {_cell(w['peak_reduction_pct'], 1)} "
            f"| {_cell(w['baseline_std_rad'], 4, w['baseline_fell'])} "
            f"| {_cell(w['compensated_std_rad'], 4, w['compensated_fell'])} "
            f"| {_cell(w['std_reduction_pct'], 1)} |"
        )
    lines += ["", f"Mean over {s['walks_compared']} walks where neither version fell: peak cut "
              f"{_cell(s['peak_reduction_pct'], 1)} %, std cut {_cell(s['std_reduction_pct'], 1)} "
              f"%; compensated walks that fell: {s['compensated_falls']}.", ""]  # fmt: skip
    for shape, t in result.tuning.items():
        lines.append(f"- {shape}: tuned objective J = {t.best_objective:.3f} (2 = no change), "
                     f"offset {t.best.as_dict()}")  # fmt: skip
    if "iteration_rms_m" in s:
        rms = ", ".join(f"{1e3 * r:.2f}" for r in s["iteration_rms_m"])  # type: ignore[union-attr]
        lines.append(f"- Algorithm 1 RMS per iteration [mm]: {rms}")
    lines += ["", *(f"![{k}]({p.name})" for k, p in figures.items()), ""]
    return "\n".join(lines)


def _per_step_std(walk: CompensatedWalk, step_s: float) -> np.ndarray:
    t, pitch = walk.time_s, walk.trunk_pitch_rad
    edges = np.arange(walk.window_s[0], walk.window_s[1] - step_s / 2, step_s)
    return np.array([np.std(pitch[(t >= a) & (t < a + step_s)]) for a in edges])


def _figures(out: Path, result: CompensateResult) -> dict[str, Path]:
    from zmpkit.analysis import compensation_plots as plots  # matplotlib only when drawing

    step_s = result.config.step_duration_s
    first = {"none": result.baseline[0]} | {k: v[0] for k, v in result.compensated.items()}
    first = {k: w for k, w in first.items() if not w.fell}
    files = {}
    if "iteration_rms_m" in result.summary:
        files["iteration_rms"] = plots.plot_iteration_rms(
            result.summary["iteration_rms_m"], out / "alg1_iteration_rms.png",
            "Algorithm 1: desired minus multibody ZMP")  # fmt: skip
    chosen = result.compensated[result.chosen][0]
    if not chosen.fell:
        measured = {"none": result.baseline[0].measured_zmp_in_world[:, 0],
                    result.chosen: chosen.measured_zmp_in_world[:, 0]}  # fmt: skip
        files["zmp_target"] = plots.plot_zmp_target(
            chosen.time_s, chosen.desired_zmp_in_world[:, 0], chosen.target_zmp_in_world[:, 0],
            measured, out / "zmp_target.png", f"{chosen.walk.label}: ZMP x",
        )  # fmt: skip
    spectra = {}
    for label, w in first.items():
        mask = (w.time_s >= w.window_s[0]) & (w.time_s <= w.window_s[1])
        spectra[label] = amplitude_spectrum(
            w.trunk_pitch_rad[mask], float(np.median(np.diff(w.time_s)))
        )
    title = f"{result.baseline[0].walk.label}: trunk pitch"
    files["spectrum"] = plots.plot_spectra(spectra, 1.0 / step_s, out / "trunk_spectrum.png", title)
    boxes = {label: _per_step_std(w, step_s) for label, w in first.items()}
    files["boxes"] = plots.plot_oscillation_boxes(boxes, out / "oscillation_std.png", title)
    return files


def write_outputs(out: Path, result: CompensateResult) -> dict[str, Path]:
    """Write summary, details, figures and report into ``out``; return them by role."""
    files = {"summary": out / SUMMARY_FILE, "details": out / DETAILS_FILE}
    files["summary"].write_text(json.dumps(result.summary, indent=2) + "\n", encoding="utf-8")
    files["details"].write_text(json.dumps(_details(result), indent=2) + "\n", encoding="utf-8")
    figures = _figures(out, result) if result.config.figures else {}
    files.update(figures)
    files["report"] = out / REPORT_FILE
    files["report"].write_text(_report(result, figures), encoding="utf-8")
    return files
