"""The report of ``zmpkit walk sweep``: which walks of the robustness matrix stood, per controller.

The sweep's target (issue "Closed-loop walking") is no fall anywhere in the matrix for a
closed-loop controller; the verdict counts the falls per controller and names the cases, and
a table breaks the count down by kind of case (speed, step duration, sideways, turning,
pushes by force, sensor faults).
"""

from __future__ import annotations

from collections.abc import Sequence

from zmpkit.analysis.provenance import capture
from zmpkit.analysis.report_document import Check, Figure, ReportDocument, Section, Table, Text
from zmpkit.analysis.robustness_plot import case_label
from zmpkit.experiments.robustness import ROBUSTNESS_COLUMNS
from zmpkit.pipelines.walk_sweep import SweepResult

__all__ = ["case_kind", "walk_sweep_document"]

_CLOSED_LOOP = ("zmpip", "dcm")


def case_kind(row: dict[str, str]) -> str:
    """The kind of a case: speed, step duration, lateral, turning, push N, or fault."""
    if row["push_n"] not in ("", "0"):
        return f"push {float(row['push_n']):g} N"
    if row["fault"]:
        return "sensor fault"
    if row["lateral_mps"] not in ("", "0"):
        return "sideways"
    if row["turn_rad_s"] not in ("", "0"):
        return "turning"
    if row["step_duration_s"] not in ("0.5",):
        return "step duration"
    return "forward speed"


def _dicts(rows: Sequence[Sequence[str]]) -> list[dict[str, str]]:
    return [dict(zip(ROBUSTNESS_COLUMNS, row, strict=True)) for row in rows]


def walk_sweep_document(result: SweepResult) -> ReportDocument:
    """The sweep's report: falls per controller, by kind of case, and the fallen cases."""
    c = result.config
    rows = _dicts(result.rows)
    title = c.robot.title
    return ReportDocument(
        title=f"zmpkit walk sweep: robustness of the virtual {title}'s walking controllers",
        summary=_summary(result),
        checks=tuple(_fall_check(rows, controller) for controller in c.controllers),
        sections=(
            Section("Falls", (_breakdown(rows, c.controllers), _fallen(rows), *_figures(result))),
            Section(
                "Data",
                (
                    Text(
                        "`robustness.csv` (one row per walk, written as each finishes; a rerun "
                        "into the same folder resumes), `summary.json` (falls per controller)."
                    ),
                ),
            ),
        ),
        provenance=capture(
            robot=c.robot, started_s=result.started_s, effects=c.effects, seed=c.seed
        ),
    )


def _fall_check(rows: list[dict[str, str]], controller: str) -> Check:
    """No fall in the matrix: the bar of a closed-loop controller, stated for open loop."""
    mine = [r for r in rows if r["controller"] == controller]
    fell = [r for r in mine if r["fell"] == "true"]
    goal = controller in _CLOSED_LOOP
    detail = f"{len(fell)} of {len(mine)} walks fell" + (
        ": "
        + "; ".join(f"{case_label(r)} ({r['fall_kind']})" for r in fell[:6])
        + (f"; and {len(fell) - 6} more" if len(fell) > 6 else "")
        if fell
        else ""
    )
    return Check(
        f"{controller}: no fall in the matrix" + ("" if goal else " (open loop, no bar)"),
        ("missed" if fell else "met") if goal else "info",
        detail,
    )


def _breakdown(rows: list[dict[str, str]], controllers: Sequence[str]) -> Table:
    """Falls by kind of case and controller."""
    kinds = list(dict.fromkeys(case_kind(r) for r in rows))
    return Table(
        ("kind of case", *(f"{k} falls / cases" for k in controllers)),
        tuple(
            (kind, *(_count(rows, controller, kind) for controller in controllers))
            for kind in kinds
        ),
        "Falls by kind of case and controller.",
    )


def _fallen(rows: list[dict[str, str]]) -> Table:
    """Every walk that fell, with when and how."""
    return Table(
        ("controller", "case", "fell at [s]", "how"),
        tuple(
            (r["controller"], case_label(r), r["fall_time_s"] or "–", r["fall_kind"] or "–")
            for r in rows
            if r["fell"] == "true"
        ),
        "Every walk that fell, with the time and kind of its fall (roll, pitch, height or "
        "stall: progress below half the commanded over two steps).",
    )


def _figures(result: SweepResult) -> list[Figure]:
    """Each controller's robustness bars, then its push matrix, captioned."""
    return [
        Figure(
            path,
            f"Robustness of `{role.removeprefix('figure_')}`: one bar per case, how long it walked "
            "[s]; green: stood to the end, red: fell (the kind of fall is named).",
        )
        for role, path in result.files.items()
        if role.startswith("figure_")
    ] + [
        Figure(
            path,
            f"The pushes of `{role.removeprefix('matrix_')}` as a matrix: force and direction "
            "down, the phase of the step at which the 0.1 s push starts across; green: stood, "
            "red: fell (its kind named); ×: a step was moved but no admissible step could "
            "capture the DCM.",
        )
        for role, path in result.files.items()
        if role.startswith("matrix_")
    ]


def _summary(result: SweepResult) -> str:
    """What the matrix holds: speeds, step durations, sideways, turning, pushes, faults."""
    c = result.config
    matrix = c.full_matrix()
    forward = sorted({x.speed_mps for x in matrix if not (x.lateral_mps or x.push_n or x.fault)})
    sideways = max(abs(x.lateral_mps) for x in matrix)
    forces = ", ".join(f"{f:g}" for f in sorted({x.push_n for x in matrix if x.push_n}))
    return (
        f"Each controller walked every case of the robustness matrix for {c.duration_s:g} s "
        f"with effects {c.effects or 'none (rigid)'}: forward {forward[0]:g}–{forward[-1]:g} "
        f"m/s, steps of 0.35–0.70 s, sideways ±{sideways:g} m/s, turning ±0.3 rad/s, pushes "
        f"of {forces} N × 0.1 s in eight directions at four phases of the step, and sensor "
        "faults (speeds scaled by the robot's walking speed over 0.2 m/s, pushes by its mass "
        "over paper B's robot's)"
        + ("; the feedback walks moved their steps to capture the DCM" if c.step_adjustment else "")
        + ". A fall is a fall: its metrics are empty in `robustness.csv`."
    )


def _count(rows: list[dict[str, str]], controller: str, kind: str) -> str:
    mine = [r for r in rows if r["controller"] == controller and case_kind(r) == kind]
    return f"{sum(r['fell'] == 'true' for r in mine)} / {len(mine)}"
