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
from zmpkit.analysis.provenance import capture
from zmpkit.analysis.report_document import (
    Block,
    Check,
    Figure,
    ReportDocument,
    Section,
    Table,
    Text,
)
from zmpkit.analysis.report_files import write_report
from zmpkit.compensate.methods import CompensatedWalk
from zmpkit.compensate.summary import ValidationWalkOutcome
from zmpkit.pipelines.walk_compensate import CompensateResult
from zmpkit.signals.spectra import amplitude_spectrum

__all__ = [
    "SUMMARY_FILE",
    "compensation_checks",
    "compensation_document",
    "compensation_sections",
    "write_walk_compensate",
]

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


def _cell(value: object, digits: int, fell: bool = False) -> str:
    if fell:
        return "fell"
    return "–" if value is None else f"{value:.{digits}f}"


def _offset_text(offset: dict[str, object]) -> str:
    """The tuned offset's parameters (its shape is the line's name)."""
    parts = []
    for name, value in offset.items():
        if name == "shape" or value in ([], ()):
            continue
        if isinstance(value, list | tuple):
            parts.append(f"{name} = [{', '.join(f'{v:.3g}' for v in value)}]")
        else:
            parts.append(
                f"{name} = {value:.4g}" if isinstance(value, float) else f"{name} = {value}"
            )
    return ", ".join(parts)


def _walk_name(w: ValidationWalkOutcome) -> str:
    name = f"{w.speed_mps:g} m/s, {w.step_duration_s:g} s steps"
    if w.robot_change:
        name += f", {w.robot_change}"
    return f"{name}, seed {w.seed}"


def compensation_checks(result: CompensateResult) -> tuple[Check, ...]:
    """The compensation's targets on walks it was not tuned on.

    It lowers the trunk's step-frequency peak and its oscillation (paper B §IV), and it makes
    no validation walk fall that stands without it (else it is rejected).
    """
    s = result.summary
    undefined = "no validation walk where both versions stood"
    checks = [
        Check(
            "makes no validation walk fall",
            "missed" if s.rejected else "met",
            f"{s.walks_made_to_fall} walk(s) made to fall: rejected, do not use it"
            if s.rejected
            else f"{s.compensated_falls} compensated walk(s) fell, none that stood without it",
        ),
    ]
    for name, value in (
        ("lowers the step-frequency peak of the trunk pitch", s.peak_reduction_pct),
        ("lowers the trunk-pitch oscillation (std)", s.std_reduction_pct),
    ):
        checks.append(
            Check(
                name,
                "undefined" if value is None else ("met" if value > 0.0 else "missed"),
                undefined
                if value is None
                else f"{abs(value):.1f} % {'lower' if value >= 0.0 else 'higher'} on average "
                f"over {s.walks_compared} held-out walks",
            )
        )
    return tuple(checks)


def compensation_sections(
    result: CompensateResult, figures: dict[str, Path]
) -> tuple[Section, ...]:
    """The validation table, the tuning, and the figures of a compensation run."""
    s = result.summary
    table = Table(
        ("validation walk", "peak, uncompensated [rad]", "peak, compensated [rad]",
         "peak cut [%]", "std, uncompensated [rad]", "std, compensated [rad]", "std cut [%]"),
        tuple(
            (_walk_name(w),
             _cell(w.baseline_peak_amplitude_rad, 4, w.baseline_fell),
             _cell(w.compensated_peak_amplitude_rad, 4, w.compensated_fell),
             _cell(w.peak_reduction_pct, 1),
             _cell(w.baseline_std_rad, 4, w.baseline_fell),
             _cell(w.compensated_std_rad, 4, w.compensated_fell),
             _cell(w.std_reduction_pct, 1))
            for w in s.validation_walks
        ),
        f"`{s.method}` (reported: {result.chosen}) on the validation walks: the trunk pitch's "
        "spectrum amplitude at the step frequency (peak) and its std over the steady walk.",
        f"Mean over the {s.walks_compared} walks where neither version fell: peak cut "
        f"{_cell(s.peak_reduction_pct, 1)} %, std cut {_cell(s.std_reduction_pct, 1)} %. "
        "fell: the walk fell, its metrics are undefined; – : undefined (a version fell).",
    )  # fmt: skip
    tuning = [
        f"- {shape}: tuned objective J = {t.best_objective:.3f} (2 = no change), offset "
        f"{_offset_text(t.best.as_dict())}"
        for shape, t in result.tuning.items()
    ]
    if s.iteration_rms_m is not None:
        tuning.append(
            "- Algorithm 1 RMS ZMP error per iteration [mm]: "
            + ", ".join(f"{1e3 * r:.2f}" for r in s.iteration_rms_m)
        )
    body: list[Block] = [table]
    if tuning:
        body.append(Text("Tuning:\n\n" + "\n".join(tuning)))
    captions = {
        "iteration_rms": "Algorithm 1: RMS of the desired minus the multibody ZMP [m] per "
        "iteration.",
        "zmp_target": "Desired ZMP, the compensated ZMP target and the measured ZMP along x [m] "
        "over time [s], uncompensated and compensated, on the first validation walk.",
        "spectrum": "Trunk-pitch amplitude spectrum [rad] over the steady window, uncompensated "
        "and compensated, on the first validation walk; the step frequency is marked.",
        "boxes": "Trunk-pitch std per step [rad], uncompensated and compensated, on the first "
        "validation walk (paper B Fig. 11).",
    }
    figs = tuple(
        Figure(path, captions.get(role, role.replace("_", " ") + "."))
        for role, path in figures.items()
    )
    return Section("Validation on walks not used for tuning", tuple(body)), Section("Figures", figs)


def compensation_document(result: CompensateResult, figures: dict[str, Path]) -> ReportDocument:
    """The report of a compensation run."""
    c = result.config
    title = c.robot.title
    how = (
        "open-loop walks (paper B's simulation); the validation walks were not used for tuning."
        if c.controller == "open"
        else f"walking controller `{c.controller}`; tuned on {len(c.tuning_walks())} walks, "
        "validated on walks that differ from all of them in speed, step duration and robot."
    )
    return ReportDocument(
        title=f"zmpkit walk compensate: `{result.summary.method}` on the virtual {title}",
        summary=f"ZMP compensation of the model abstractions (paper B §IV), effects {c.effects}; "
        + how,
        checks=compensation_checks(result),
        sections=(
            *compensation_sections(result, figures),
            Section(
                "Data",
                (
                    Text(
                        "`summary.json` (the means and one entry per validation walk), "
                        "`compensation.json` (tuning history and every walk)."
                    ),
                ),
            ),
        ),
        provenance=capture(
            robot=c.robot,
            started_s=result.started_s,
            effects=c.effects,
            seed=c.seed,
            extra=(("controller", c.controller), ("method", c.method), ("quick", str(c.quick))),
        ),
    )


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
