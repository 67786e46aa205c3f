"""The report of ``zmpkit walk``: did the robot stand, how it walked, and paper B's figures.

The walk's own targets are few and plain: it stands for the whole walk, and it steps as
commanded (no footstep limit shortened a step). Speed and trunk oscillation have no bar of
their own; they are stated against the commanded and the planned walk (paper B reports them
so). A fallen walk's metrics are undefined, and the verdict says why.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

from zmpkit.analysis.labels import EFFECT_NAMES, effects_name
from zmpkit.analysis.provenance import capture_run
from zmpkit.analysis.report_document import (
    Block,
    Check,
    Figure,
    ReportDocument,
    Section,
    Status,
    Table,
    Text,
    Video,
)
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import HEADING_TOLERANCE_RAD, WalkSummary
from zmpkit.pipelines.walk import WalkResult
from zmpkit.pipelines.walk_figures import JOINT_PLOT_STEPS

__all__ = [
    "EFFECT_NAMES",
    "effects_name",
    "fmt",
    "walk_checks",
    "walk_document",
    "walk_figures",
    "walk_metrics_table",
]


def fmt(value: float | None, spec: str, unit: str = "") -> str:
    """``value`` formatted with its unit, or "–" for a value that is undefined."""
    if value is None:
        return "–"
    return f"{value:{spec}}" + (f" {unit}" if unit else "")


def walk_checks(summary: WalkSummary, prefix: str = "") -> tuple[Check, ...]:
    """The walk's targets: it stood; it stepped as commanded; speed and oscillation stated."""
    lead = f"{prefix}: " if prefix else ""
    why = _why_undefined(summary)
    checks = [_stands(summary, lead), _steps_as_commanded(summary, lead)]
    if summary.heading_error_max_rad is not None or summary.fell:
        checks.append(_heading_check(summary, lead, why))
    checks += _speed_checks(summary, lead, why)
    if summary.adjusted_steps:
        checks.append(_stepping_check(summary, lead))
    amplitude = summary.trunk_pitch_peak_amplitude_rad
    checks.append(
        Check(
            f"{lead}trunk-pitch oscillation (no bar)",
            "undefined" if amplitude is None else "info",
            why
            if amplitude is None
            else f"peak {fmt(amplitude, '.4f', 'rad')} at "
            f"{fmt(summary.trunk_pitch_peak_hz, '.2f', 'Hz')} (step frequency "
            f"{summary.step_frequency_hz:.2f} Hz)",
        )
    )
    return tuple(checks)


def _stands(summary: WalkSummary, lead: str) -> Check:
    """Met when the walk did not fall."""
    return Check(
        f"{lead}stands for the whole walk",
        "missed" if summary.fell else "met",
        f"fell at {summary.fall_time_s:.2f} s ({summary.fall_kind})"
        if summary.fell and summary.fall_time_s is not None
        else "stood to the end",
    )


def _steps_as_commanded(summary: WalkSummary, lead: str) -> Check:
    """Met when no footstep limit shortened a step."""
    return Check(
        f"{lead}steps as commanded",
        "missed" if summary.clamped_step_limits else "met",
        "steps shortened by the footstep limits: " + ", ".join(summary.clamped_step_limits)
        if summary.clamped_step_limits
        else "no footstep limit shortened a step",
    )


def _heading_check(summary: WalkSummary, lead: str, why: str) -> Check:
    """The IMU yaw against the plan's: judged in closed loop, stated in open loop [rad]."""
    heading = summary.heading_error_max_rad
    open_loop = summary.controller == "open"  # no heading feedback: stated, not judged
    status: Status = "undefined"
    if heading is not None:
        status = "info" if open_loop else _met(heading <= HEADING_TOLERANCE_RAD)
    bar = "(open loop: no bar)" if open_loop else f"against the bar ≤ {HEADING_TOLERANCE_RAD:g} rad"
    return Check(
        f"{lead}keeps its heading (IMU yaw against the plan's)",
        status,
        why
        if heading is None
        else f"largest error {heading:.3f} rad {bar} (at the end "
        f"{summary.heading_error_end_rad:+.3f} rad)",
    )


def _speed_checks(summary: WalkSummary, lead: str, why: str) -> list[Check]:
    """The forward speed and the speed along the path against the commanded [m/s]."""
    speed = summary.mean_speed_mps
    path = summary.path_speed_mps
    commanded_path = math.hypot(summary.commanded_speed_mps, summary.commanded_lateral_speed_mps)
    return [
        Check(
            f"{lead}forward speed (no bar)",
            "undefined" if speed is None else "info",
            why
            if speed is None
            else f"{speed:.3f} m/s against {summary.commanded_speed_mps:.3f} m/s commanded "
            f"({_pct(speed, summary.commanded_speed_mps)})",
        ),
        Check(
            f"{lead}speed along the path (no bar)",
            "undefined" if path is None else "info",
            (why if speed is None else "the steady window is shorter than two gait cycles")
            if path is None
            else f"{path:.3f} m/s against {commanded_path:.3f} m/s commanded "
            f"({_pct(path, commanded_path)}); what a turning or sideways walk makes, where the "
            "forward speed is the advance along x",
        ),
    ]


def _stepping_check(summary: WalkSummary, lead: str) -> Check:
    """The adjusted steps: met when each captured the DCM within the legs' limits."""
    missed = summary.uncaptured_steps
    return Check(
        f"{lead}every adjusted step captures the DCM",
        "missed" if missed else "met",
        f"{summary.adjusted_steps} step(s) adjusted, {missed} where no admissible step captures "
        "the DCM: " + "; ".join(summary.step_events),
    )


def _met(ok: bool) -> Status:
    return "met" if ok else "missed"


def _pct(value: float, reference: float) -> str:
    if reference == 0.0:
        return "commanded 0"
    return f"{100.0 * (value - reference) / abs(reference):+.1f} %"


def _why_undefined(summary: WalkSummary) -> str:
    if summary.fell:
        return "undefined: the robot fell (a fallen walk's metrics are null)"
    return "undefined: the steady window is too short to measure it"


def walk_metrics_table(summaries: Mapping[str, WalkSummary], caption: str) -> Table:
    """One column per walk: speeds, trunk oscillation, feet distance and slip, IK errors."""
    names = tuple(summaries)
    rows: list[tuple[str, ...]] = []

    def row(name: str, values: list[str]) -> None:
        rows.append((name, *values))

    s = list(summaries.values())
    row("fell", [f"yes, {x.fall_kind} at {x.fall_time_s:.2f} s" if x.fell and x.fall_time_s
                 is not None else "no" for x in s])  # fmt: skip
    row("speed, measured [m/s]", [fmt(x.mean_speed_mps, ".4f") for x in s])
    row("speed along the path [m/s]", [fmt(x.path_speed_mps, ".4f") for x in s])
    row("speed, planned CoM [m/s]", [fmt(x.planned_speed_mps, ".4f") for x in s])
    row("speed, commanded [m/s]", [f"{x.commanded_speed_mps:.4f}" for x in s])
    row("trunk-pitch peak [Hz]", [fmt(x.trunk_pitch_peak_hz, ".2f") for x in s])
    row(
        "trunk-pitch peak amplitude [rad]",
        [fmt(x.trunk_pitch_peak_amplitude_rad, ".4f") for x in s],
    )
    row("amplitude at the step frequency [rad]",
        [fmt(x.trunk_pitch_step_frequency_amplitude_rad, ".4f") for x in s])  # fmt: skip
    row("trunk-pitch std [rad]", [fmt(x.trunk_pitch_std_rad, ".4f") for x in s])
    row("feet distance in double support [m]",
        [fmt(x.mean_double_support_foot_distance_m, ".4f") for x in s])  # fmt: skip
    row("planned feet distance [m]",
        [fmt(x.planned_double_support_foot_distance_m, ".4f") for x in s])  # fmt: skip
    row("foot slip per stance, along x [m]", [fmt(x.foot_slip_x_m, "+.4f") for x in s])
    row("largest IK CoM / foot error [m]",
        [f"{x.ik_max_com_error_m:.1e} / {x.ik_max_foot_error_m:.1e}" for x in s])  # fmt: skip
    row("steady window [s]", [f"{x.window_s[0]:.2f} – {x.window_s[1]:.2f}" for x in s])
    notes = (
        "Metrics are taken over the steady window (from the end of the second step to one "
        "step before the end); – : undefined (the robot fell, or the window was too short). "
        "Foot slip: negative is backwards."
    )
    return Table(("metric", *names), tuple(rows), caption, notes)


_CAPTIONS = {
    "trunk_pitch": "Trunk pitch [rad] from the IMU over time [s] ({label}); shaded: the steady "
    "window {window} s of the summary's metrics; a red line marks a fall. Paper B Fig. 2 shows "
    "the same oscillation at the step frequency.",
    "trunk_roll": "Trunk roll [rad] from the IMU over time [s] ({label}): the sideways sway "
    "that grows into a roll fall (dotted: the tilt at which a walk counts as fallen, drawn when "
    "the roll comes near it); a red line marks a fall.",
    "spectrum": "Amplitude spectrum of the trunk pitch [rad] over the steady window "
    "{window} s (the window of the summary's metrics, so its peak is the summary's) ({label}); "
    "the step frequency and the peak are marked (paper B Fig. 12).",
    "feet": "Sole positions along world x [m] over time [s], drawn while each foot touches the "
    "floor ({label}); paper B Fig. 3.",
    "feet_distance": "Distance between the feet along the walking heading [m] in double support "
    "over time [s], measured at the soles and as planned by the footstep plan that was walked "
    "(shortened steps included) ({label}); paper B Fig. 4.",
}


def walk_figures(
    files: Mapping[str, Path], label: str, window_s: tuple[float, float]
) -> tuple[Figure, ...]:
    """The walk's figures (``WalkResult.files`` minus its data files), captioned."""
    window = f"{window_s[0]:.2f}–{window_s[1]:.2f}"
    figures = []
    for role, path in files.items():
        if path.suffix.lower() != ".png":
            continue
        template = _CAPTIONS.get(role)
        if template is None:
            caption = (
                f"Joint `{role}` over {JOINT_PLOT_STEPS} steps: commanded and measured angle "
                f"[rad] with the torque [N·m] (top) and the tracking error, commanded − "
                f"measured [rad] (bottom), over time [s] ({label}); paper B Figs. 7–9."
            )
        else:
            caption = template.format(label=label, window=window)
        figures.append(Figure(path, caption))
    return tuple(figures)


def walk_label(config: WalkConfig) -> str:
    """A short label of a walk: speed, step, effects, controller."""
    return (
        f"{config.speed_mps:g} m/s, {config.step_duration_s:g} s steps, "
        f"{effects_name(config.effects)}, controller {config.controller}"
    )


def walk_document(result: WalkResult) -> ReportDocument:
    """The report of one walk."""
    c, s = result.config, result.summary
    title = c.robot.title
    label = walk_label(c)
    summary = (
        f"The virtual {title} walked {c.duration_s:g} s at a commanded {c.speed_mps:g} m/s "
        f"(lateral {c.lateral_speed_mps:g} m/s, turning {c.turn_rate_rps:g} rad/s) with "
        f"{c.step_duration_s:g} s steps: 3D-LIPM preview-control pattern, whole-body IK, "
        f"controller `{c.controller}`, {effects_name(c.effects)}"
        f"{c.robot.simulated_effects_note(c.effects, c.truth)}."
        + (f" Pushes: {', '.join(s.pushes)}." if s.pushes else "")
    )
    body: list[Block] = [
        walk_metrics_table({label: s}, "The walk's metrics over the steady window."),
        *walk_figures(result.files, label, s.window_s),
    ]
    if "video" in result.files:
        body.append(Video(result.files["video"], f"The walk ({label}), rendered from the record."))
    data = Text(
        "Data: `summary.json` (these metrics, `null` where undefined) and `timeseries.csv` "
        "(one row per 10 ms frame: planned and measured ZMP, CoM, soles, joints)."
    )
    return ReportDocument(
        title=f"zmpkit walk: the virtual {title} walking (paper B)",
        summary=summary,
        checks=walk_checks(s),
        sections=(Section("The walk", (*body, data)),),
        provenance=capture_run(c, result.started_s, (("controller", c.controller),)),
    )
