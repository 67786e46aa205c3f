"""The report of ``zmpkit walk compensate``: the targets, the validation table, the figures.

The compensation's targets (:func:`compensation_checks`) are judged on walks it was not tuned
on; :func:`compensation_sections` also serve the demo's report.
"""

from __future__ import annotations

from pathlib import Path

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
from zmpkit.compensate.summary import ValidationWalkOutcome
from zmpkit.pipelines.walk_compensate import CompensateResult

__all__ = ["compensation_checks", "compensation_document", "compensation_sections"]


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
