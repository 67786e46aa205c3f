"""``summary.json``, ``compensation.json``, ``report.md`` and the figures of a compensation run.

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
from zmpkit.compensate.methods import CompensatedWalk
from zmpkit.compensate.summary import ValidationWalkOutcome
from zmpkit.pipelines.walk_compensate import CompensateResult
from zmpkit.robots.registry import get_robot
from zmpkit.signals.spectra import amplitude_spectrum

__all__ = [
    "REPORT_FILE",
    "SUMMARY_FILE",
    "write_walk_compensate",
]

SUMMARY_FILE = "summary.json"
REPORT_FILE = "report.md"
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


def _cell(value: object, digits: int, fell: bool = False) -> str:
    if fell:
        return "fell"
    return "–" if value is None else f"{value:.{digits}f}"


def _report(result: CompensateResult, figures: dict[str, Path]) -> str:
    s = result.summary
    lines = [
        f"## Walking compensation: `{s.method}` (reported: {result.chosen})", "",
        f"Virtual {get_robot(result.config.robot).title}, effects {result.config.effects}; "
        + ("validation walks not used for tuning."
           if result.config.controller == "open" else
           f"walking controller {result.config.controller}; tuned on "
           f"{len(result.config.tuning_walks())} walks, validated on walks that differ from "
           "all of them in speed, step duration and robot."),
        "Peak = trunk-pitch spectrum amplitude at the step frequency; std over the steady walk.",
        "", "| walk | peak before [rad] | peak after [rad] | peak cut [%] | std before [rad] "
        "| std after [rad] | std cut [%] |", "|---|---|---|---|---|---|---|",
    ]  # fmt: skip
    for w in s.validation_walks:
        name = f"{w.speed_mps:g} m/s"
        if w.step_duration_s != 0.5:
            name += f", {w.step_duration_s:g} s steps"
        if w.robot_change:
            name += f", {w.robot_change}"
        lines.append(
            f"| {name} seed {w.seed} "
            f"| {_cell(w.baseline_peak_amplitude_rad, 4, w.baseline_fell)} "
            f"| {_cell(w.compensated_peak_amplitude_rad, 4, w.compensated_fell)} "
            f"| {_cell(w.peak_reduction_pct, 1)} "
            f"| {_cell(w.baseline_std_rad, 4, w.baseline_fell)} "
            f"| {_cell(w.compensated_std_rad, 4, w.compensated_fell)} "
            f"| {_cell(w.std_reduction_pct, 1)} |"
        )
    lines += ["", f"Mean over {s.walks_compared} walks where neither version fell: peak cut "
              f"{_cell(s.peak_reduction_pct, 1)} %, std cut {_cell(s.std_reduction_pct, 1)} "
              f"%; compensated walks that fell: {s.compensated_falls}.", ""]  # fmt: skip
    if s.rejected:
        lines += [f"**Rejected**: the compensation made {s.walks_made_to_fall} validation "
                  "walk(s) fall that stand without it; do not use it.", ""]  # fmt: skip
    for shape, t in result.tuning.items():
        lines.append(f"- {shape}: tuned objective J = {t.best_objective:.3f} (2 = no change), "
                     f"offset {t.best.as_dict()}")  # fmt: skip
    if s.iteration_rms_m is not None:
        rms = ", ".join(f"{1e3 * r:.2f}" for r in s.iteration_rms_m)
        lines.append(f"- Algorithm 1 RMS per iteration [mm]: {rms}")
    lines += ["", *(f"![{k}]({p.name})" for k, p in figures.items()), ""]
    return "\n".join(lines)


def _per_step_std(walk: CompensatedWalk, step_s: float) -> np.ndarray:
    t, pitch = walk.time_s, walk.trunk_pitch_rad
    edges = np.arange(walk.window_s[0], walk.window_s[1] - step_s / 2, step_s)
    return np.array([np.std(pitch[(t >= a) & (t < a + step_s)]) for a in edges])


def _figures(out: Path, result: CompensateResult) -> dict[str, Path]:

    step_s = result.config.step_duration_s
    first = {"none": result.baseline[0]} | {k: v[0] for k, v in result.compensated.items()}
    first = {k: w for k, w in first.items() if not w.fell}
    files = {}
    if result.summary.iteration_rms_m is not None:
        files["iteration_rms"] = plots.plot_iteration_rms(
            list(result.summary.iteration_rms_m), out / "alg1_iteration_rms.png",
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


def write_walk_compensate(result: CompensateResult, out_dir: str | Path) -> CompensateResult:
    """Write summary, details, figures and report into ``out_dir``.

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
    files["report"] = out / REPORT_FILE
    files["report"].write_text(_report(result, figures), encoding="utf-8")
    return replace(result, files=files)
