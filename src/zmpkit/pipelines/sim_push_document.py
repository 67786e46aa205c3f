"""The report of ``zmpkit sim push``: each ZMP step (or push) and how the robot settled.

A step sweep has no bar of paper A (that is ``zmpkit balance``); its targets are that each
trial settles, so that its steady-state ZMP is defined. The steady ZMP, its error and the
overshoot are stated per target (paper A Fig. 14).
"""

from __future__ import annotations

from zmpkit.analysis.provenance import capture_run
from zmpkit.analysis.report_document import Check, Figure, ReportDocument, Section, Table, Text
from zmpkit.experiments import TrialResponse
from zmpkit.pipelines.sim_push import SimPushResult

__all__ = ["sim_push_document"]


def _cell(value: float | None, spec: str) -> str:
    return "–" if value is None else f"{value:{spec}}"


def sim_push_document(result: SimPushResult) -> ReportDocument:
    """The step sweep's report: one check per trial (settled or not), a table, the figure."""
    config = result.config
    title = config.robot.title
    push = (
        f" A push of {config.push.force_n:g} N for {config.push.duration_s:g} s follows the step."
        if config.push is not None
        else ""
    )
    figure = Figure(
        result.files["figure"],
        f"Measured force–torque ZMP [m] (solid) and the LIPM's expected ZMP l·sin θ [m] (dashed) "
        f"over time since the step [s], one colour per target ({config.plane}; paper A Fig. 14).",
    )
    return ReportDocument(
        title=f"zmpkit sim push: ZMP steps on the virtual {title}",
        summary=(
            f"{len(result.responses)} LIPM lean steps in the {config.plane} plane to targets "
            f"{', '.join(f'{x:g}' for x in config.targets_m)} m, {config.hold_s:g} s hold each, "
            f"effects {config.effects}.{push}"
        ),
        checks=tuple(_settles(r) for r in result.responses),
        sections=(
            Section("Steps", (_steady_state_table(result), figure)),
            Section(
                "Data",
                (
                    Text(
                        "`steady_state.csv` (this table) and the dataset: one CSV per trial "
                        "and `meta.json` (read it with `zmpkit.experiments.read_step_dataset`)."
                    ),
                ),
            ),
        ),
        provenance=capture_run(config, result.started_s),
    )


def _settles(r: TrialResponse) -> Check:
    """The trial's target: it settles, so that its steady-state ZMP is defined."""
    span = r.steady_window_s[1] - r.steady_window_s[0]
    if r.settled:
        detail = f"ZMP {r.steady_state:.5f} m" if r.steady_state is not None else "settled"
        if r.error_pct is not None:
            detail += f", error {r.error_pct:+.1f} %"
        return Check(f"target {r.zmp_ref:g} m settles", "met", detail)
    spread = "undefined" if r.tail_spread_m is None else f"{1e3 * r.tail_spread_m:.1f} mm"
    return Check(
        f"target {r.zmp_ref:g} m settles",
        "undefined",
        f"its ZMP spans {spread} over the last {span:g} s (a longer --hold may help)",
    )


def _steady_state_table(result: SimPushResult) -> Table:
    """Steady ZMP [m], error [%], overshoot [%] and whether it settled, per target."""
    rows = tuple(
        (
            f"{r.zmp_ref:g}",
            _cell(r.steady_state, ".5f"),
            _cell(r.error_pct, "+.1f"),
            _cell(r.overshoot_pct, ".1f"),
            "yes" if r.settled else "no",
        )
        for r in result.responses
    )
    return Table(
        ("ZMP target [m]", "steady ZMP [m]", "error [%]", "overshoot [%]", "settled"),
        rows,
        "Steady state of each trial: mean force–torque ZMP over its last "
        f"{result.responses[0].steady_window_s[1] - result.responses[0].steady_window_s[0]:g} s"
        if result.responses
        else "Steady state of each trial.",
        "– : undefined (target 0, where a relative error has no meaning, or a trial that did "
        "not settle).",
    )
