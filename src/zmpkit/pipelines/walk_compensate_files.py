"""``summary.json``, ``compensation.json``, the report and the figures of a compensation run.

The summary (:class:`~zmpkit.compensate.summary.CompensationSummary`) holds the keys of
:data:`~zmpkit.compensate.summary.SUMMARY_KEYS` (plus ``iteration_rms_m`` for ``alg1``):
means over the validation walks of the step-frequency amplitude and the std of the trunk
pitch, without and with the compensation, their reductions [%], and one entry per walk.
Walks whose uncompensated version fell are listed but left out of the means.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np

from zmpkit.analysis import compensation_plots as plots
from zmpkit.analysis.labels import compensation_name
from zmpkit.analysis.report_files import write_report
from zmpkit.compensate.methods import CompensatedWalk
from zmpkit.compensate.summary import ValidationWalkOutcome
from zmpkit.pipelines.walk_compensate import CompensateResult
from zmpkit.pipelines.walk_compensate_document import compensation_document
from zmpkit.signals.spectra import amplitude_spectrum

__all__ = ["DETAILS_FILE", "SUMMARY_FILE", "write_walk_compensate"]

SUMMARY_FILE = "summary.json"
DETAILS_FILE = "compensation.json"


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
        label: [
            ValidationWalkOutcome.of(b, c).as_dict()
            for b, c in zip(result.baseline, walks, strict=True)
        ]
        for label, walks in result.compensated.items()
    }
    return {"chosen": result.chosen, "tuning": tuning, "validation": validation}


def _per_step_std(walk: CompensatedWalk, step_s: float) -> np.ndarray:
    t, pitch = walk.time_s, walk.trunk_pitch_rad
    edges = np.arange(walk.window_s[0], walk.window_s[1] - step_s / 2, step_s)
    return np.array([np.std(pitch[(t >= a) & (t < a + step_s)]) for a in edges])


def _figures(out: Path, result: CompensateResult) -> dict[str, Path]:

    step_s = result.config.step_duration_s
    first = {compensation_name("none"): result.baseline[0]} | {
        compensation_name(k): v[0] for k, v in result.compensated.items()
    }
    first = {k: w for k, w in first.items() if not w.fell}
    files = {}
    if result.summary.iteration_rms_m is not None:
        files["iteration_rms"] = plots.plot_iteration_rms(
            list(result.summary.iteration_rms_m), out / "alg1_iteration_rms.png",
            "Algorithm 1: desired minus multibody ZMP")  # fmt: skip
    chosen = result.compensated[result.chosen][0]
    if not chosen.fell:
        measured = {
            compensation_name("none"): result.baseline[0].measured_zmp_in_world[:, 0],
            compensation_name(result.chosen): chosen.measured_zmp_in_world[:, 0],
        }
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


def write_walk_compensate(
    result: CompensateResult, out_dir: str | Path, report_format: str = "html"
) -> CompensateResult:
    """Write summary, details, figures and the report (``report_format``) into ``out_dir``.

    Returns:
        ``result`` with the files written, by role.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = {"summary": out / SUMMARY_FILE, "details": out / DETAILS_FILE}
    summary = result.summary.as_dict()
    files["summary"].write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    files["details"].write_text(json.dumps(_details(result), indent=2) + "\n", encoding="utf-8")
    figures = _figures(out, result) if result.config.figures else {}
    files.update(figures)
    files["report"] = write_report(compensation_document(result, figures), out, report_format)
    return replace(result, files=files)
