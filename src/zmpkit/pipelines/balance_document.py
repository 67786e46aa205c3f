"""The report of ``zmpkit balance``: paper A's bars per plane, identification, Table 1, figures.

The verdict states each of paper A's bars per plane (met, missed, or undefined and why), the
transient counts, and the warnings (targets the controllers extrapolated, trials that did not
settle). Every target says whether the error model was fitted on it or held out, so no fitted
target passes for a validated one. Empty cells of Table 1 carry a mark whose note says why.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from zmpkit.analysis.balance_targets import TRANSIENT_FROM_M, balance_targets
from zmpkit.analysis.balance_validation import (
    MIN_STEP_NOISE_RATIO,
    ControllerOutcome,
    step_stands_out,
)
from zmpkit.analysis.balance_verdict import Bar, PlaneVerdict
from zmpkit.analysis.provenance import capture
from zmpkit.analysis.report_document import (
    Block,
    Check,
    Figure,
    ReportDocument,
    Section,
    Table,
    Text,
    Video,
)
from zmpkit.analysis.table1 import Table1Row
from zmpkit.identify import TERMS
from zmpkit.identify.error_model import COEFFICIENT_UNITS
from zmpkit.identify.params import PlaneIdentification
from zmpkit.pipelines.balance import BalanceConfig, BalanceResult, PlaneResult

__all__ = [
    "balance_checks",
    "balance_document",
    "balance_figures",
    "controller_blocks",
    "identification_blocks",
    "step_trial_videos",
    "table1_table",
]

_NAMES = {
    "lipm": "LIPM",
    "dlipm": "DLIPM",
    "linear": "linear",
    "lipm_pid": "LIPM+PID",
    "dlipm_fb": "DLIPM+feedback",
}


def balance_document(
    result: BalanceResult,
    figures: Sequence[Figure],
    verdicts: dict[str, PlaneVerdict],
    extra_sections: Sequence[Section] = (),
    videos: Sequence[Video] = (),
) -> ReportDocument:
    """The balance run's report: verdict, then one section per plane, then the data."""
    c = result.config
    title = c.robot.title
    sections = [
        _plane_section(plane, [f for f in figures if f"_{plane.plane}" in f.path.name])
        for plane in result.planes.values()
    ]
    if videos:
        sections.append(Section("The robot", tuple(videos)))
    sections += [*extra_sections, _data_section()]
    return ReportDocument(
        title=f"zmpkit balance: LIPM vs gain-scheduled DLIPM on the virtual {title} (paper A §4)",
        summary=_summary(c, title),
        checks=balance_checks(result, verdicts),
        sections=tuple(sections),
        provenance=capture(
            robot=c.robot,
            started_s=result.started_s,
            truth=c.truth,
            effects=c.effects,
            seed=c.seed,
            extra=(
                ("hold", _hold(c)),
                ("pacing", _pace(c)),
                ("DLIPM ζ", f"{c.zeta:g}"),
                ("ZMP feedback", _feedback(c)),
            ),
        ),
    )


def _summary(c: BalanceConfig, title: str) -> str:
    fitted = set(np.round(c.fit_targets_m, 6))
    held_out = [x for x in c.targets_m if round(x, 6) not in fitted]
    return (
        f"Paper A's balance experiment on the virtual {title}, {_effects(c.effects)}"
        f"{c.robot.simulated_effects_note(c.effects, c.truth)}: LIPM "
        "step trials; identification of the steady-state error model from the force–torque "
        f"ZMP, fitted on the LIPM steps at **{_targets(c.fit_targets_m)} m**; then every target "
        "under the gain-scheduled DLIPM (paper A eq. 7–11, ζ = "
        f"{c.zeta:g}, scheduled on the error model) and under one linear correction. Held out "
        f"from the fit: **{_targets(held_out) + ' m' if held_out else 'no target'}**. "
        f"Trials: {_hold(c)}; DLIPM {_pace(c)}."
        + (
            " With `--dlipm-feedback`, also the LIPM and the DLIPM each with a clamped PI on "
            f"the measured ZMP (LIPM+PID, DLIPM+feedback); {_feedback(c)}."
            if c.dlipm_feedback
            else ""
        )
    )


def _feedback(c: BalanceConfig) -> str:
    if not c.dlipm_feedback:
        return "off"
    if not c.faults:
        return "on, clean F-T readings"
    return f"on, F-T faults injected into its readings: {', '.join(c.faults)}"


def _effects(effects: str) -> str:
    return {"all": "every effect on", "none": "a rigid robot (effects off)"}.get(
        effects, f"effects {effects}"
    )


def _targets(values: Sequence[float]) -> str:
    return ", ".join(f"{x:g}" for x in values)


def _hold(c: BalanceConfig) -> str:
    if c.max_hold_s is None:
        return f"hold {c.hold_s:g} s"
    return f"hold {c.hold_s:g} s, extended until settled up to {c.max_hold_s:g} s"


def _pace(c: BalanceConfig) -> str:
    if c.servo_paced:
        return f"paced by the servos' acceleration limit (time scale ≥ {c.time_scale:.3g})"
    return f"at a fixed time scale {c.time_scale:.3f}"


def step_trial_videos(result: BalanceResult, paths: Sequence[Path]) -> tuple[Video, ...]:
    """The step-trial videos of a run, captioned."""
    plane = next(iter(result.planes), "sagittal")
    target = max(result.config.targets_m, key=abs)
    return tuple(
        Video(
            path,
            f"The virtual robot under the scheduled DLIPM, stepping its ZMP to {target:g} m "
            f"({plane}), rendered from the recorded joint angles; time is simulated time.",
        )
        for path in paths
    )


def balance_checks(result: BalanceResult, verdicts: dict[str, PlaneVerdict]) -> tuple[Check, ...]:
    """Paper A's bars per plane, the transient counts, and the warnings."""
    fitted = set(np.round(result.config.fit_targets_m, 6))
    checks: list[Check] = []
    for name, verdict in verdicts.items():
        rows = result.planes[name].rows
        far = max(rows, key=lambda r: abs(r.zmp_ref))
        role = "fitted" if round(far.zmp_ref, 6) in fitted else "held out"
        for bar in verdict.bars:
            checks.append(_bar_check(name, bar, far.zmp_ref, role))
        targets = balance_targets(name, rows)
        for what, (lower, total) in (
            ("lower overshoot", targets.overshoot_lower),
            ("shorter 5 % settling", targets.settling_lower),
        ):
            checks.append(
                Check(
                    f"{name}: DLIPM {what} than LIPM (no bar)",
                    "info",
                    f"at {lower} of {total} targets ≥ {TRANSIENT_FROM_M:g} m",
                )
            )
        checks += _feedback_checks(name, rows)
        checks += [Check(f"{name}: warning", "info", w) for w in verdict.warnings]
    for name, why in result.failed_planes.items():
        checks.append(Check(f"{name}: paper A's bars", "undefined", f"the plane failed: {why}"))
    return tuple(checks)


def _feedback_checks(plane: str, rows: Sequence[Table1Row]) -> list[Check]:
    """DLIPM+feedback against the LIPM and the DLIPM (no bar of paper A): error ratios."""
    if not any(r.dlipm_fb is not None for r in rows):
        return []
    far = max(rows, key=lambda r: abs(r.zmp_ref))
    means = {}
    for name in ("lipm", "dlipm", "lipm_pid", "dlipm_fb"):
        errors = [r.outcomes()[name].error_pct for r in rows if r.zmp_ref != 0.0]
        means[name] = (
            None
            if not errors or any(e is None for e in errors)
            else float(np.mean([abs(e) for e in errors if e is not None]))
        )
    far_fb = far.outcomes()["dlipm_fb"].error_pct
    detail = (
        f"error at {far.zmp_ref:g} m {_pct_text(far_fb)}; mean |error| over targets ≠ 0: "
        f"DLIPM+feedback {_pct_text(means['dlipm_fb'])}, DLIPM {_pct_text(means['dlipm'])}, "
        f"LIPM+PID {_pct_text(means['lipm_pid'])}, LIPM {_pct_text(means['lipm'])}"
    )
    lipm, fb = means["lipm"], means["dlipm_fb"]
    if lipm and fb is not None:
        detail += f"; ratio DLIPM+feedback / LIPM {fb / lipm:.3f}"
    return [Check(f"{plane}: DLIPM+feedback (no bar of paper A)", "info", detail)]


def _pct_text(value: float | None) -> str:
    return "undefined (a trial did not settle)" if value is None else f"{value:.2f} %"


def _bar_check(plane: str, bar: Bar, far_m: float, role: str) -> Check:
    if bar.name == "far error ratio":
        name = f"{plane}: |DLIPM error| / |LIPM error| at {far_m:g} m (a {role} target)"
    else:
        name = f"{plane}: mean |DLIPM error| / mean |LIPM error|, targets ≠ 0"
    value = "undefined" if bar.value is None else f"{bar.value:.3f}"
    detail = f"{value} against the bar ≤ {bar.limit:.2f}"
    if bar.why:
        detail += f": {bar.why}"
    status = bar.state if bar.state in ("met", "missed", "undefined") else "undefined"
    return Check(name, status, detail)  # type: ignore[arg-type]


def _plane_section(plane: PlaneResult, figures: Sequence[Figure]) -> Section:
    name = plane.plane
    return Section(
        f"{name.capitalize()} plane",
        subsections=(
            Section(
                "Identification",
                identification_blocks(
                    plane.identification.planes[name], plane.plane, plane.lean_length_m
                ),
            ),
            Section("The controller that ran", controller_blocks(plane)),
            Section("Table 1", (table1_table(plane.rows),)),
            Section("Figures", tuple(figures)),
        ),
    )


def identification_blocks(
    ident: PlaneIdentification, plane: str, lean_length_m: float
) -> tuple[Table, Text]:
    """The error model with its coefficients and units, its residuals [mm] and its data."""
    fit = ident.error_fit
    residual_mm = 1e3 * np.abs(np.asarray(fit.residuals, dtype=float))
    coefficients = Table(
        ("coefficient", "value", "95 % interval", "unit"),
        tuple(
            (name, f"{value:.5g}", f"{lo:.5g} … {hi:.5g}", COEFFICIENT_UNITS[name])
            for name, value, (lo, hi) in zip(
                TERMS[fit.kind], fit.model.coefficients, fit.confidence_intervals, strict=True
            )
        ),
        f"Error model of the {plane} plane: **{fit.kind}**, `{fit.model.equation}` (ZMPs in m).",
    )
    shares = fit.weight_shares
    near = sum(float(w) for u, w in zip(fit.x_cmd, shares, strict=True) if abs(u) <= 0.0201)
    low, high = fit.fitted_range
    loo = ", ".join(
        f"{k} {1e3 * v:.3f} mm" if v is not None else f"{k} undefined"
        for k, v in fit.loo_rmse.items()
    )
    p = ident.params
    transient = (
        f"ζ = {p.zeta:.3f}, ω_n = {p.omega_n:.2f} rad/s"
        if p.zeta is not None and p.omega_n is not None
        else "no transient fit succeeded"
    )
    text = Text(
        f"- fit residuals: largest {residual_mm.max(initial=0.0):.2f} mm, RMS "
        f"{float(np.sqrt(np.mean(residual_mm**2))) if residual_mm.size else 0.0:.2f} mm "
        f"(R² = {fit.r_squared:.4f} says little here: the data span the whole range)\n"
        f"- why this model: {fit.reason}\n"
        f"- leave-one-out RMSE of the candidates: {loo}\n"
        f"- weights: {fit.weighting}, between-trial scatter τ = {fit.scatter:.3g} m; the "
        f"trials at |x_cmd| ≤ 0.02 m hold {100 * near:.1f} % of the weight\n"
        f"- fitted range (measured ZMP): {low:.4g} … {high:.4g} m; beyond it the controllers "
        "extrapolate the model (marked † in Table 1, shaded in the measured-vs-reference "
        "figure)\n"
        f"- mean transient of the LIPM steps: {transient}\n"
        f"- trials left out of the fit: {'; '.join(ident.excluded) or 'none'}\n"
        f"- pendulum: lean length {lean_length_m:.4f} m (ankle pivot to CoM)\n"
    )
    return coefficients, text


def controller_blocks(plane: PlaneResult) -> tuple[Block, ...]:
    """The scheduled DLIPM of this plane: its gains per target, its limits and pacing."""
    factory = plane.factories.get("dlipm")
    if factory is None:
        return (Text("No scheduled DLIPM ran in this plane."),)
    schedule = factory.schedule()
    rows = []
    for row in plane.rows:
        x = row.zmp_ref
        dlipm = schedule.dlipm(x)
        rows.append(
            (
                f"{x:g}" + (" †" if schedule.extrapolates(x) else ""),
                f"{float(schedule.commanded_zmp(x)):.5f}",
                f"{float(schedule.steady_angle(x)):.5f}",
                f"{float(schedule.dc_gain(x)):.4f}",
                f"{float(schedule.k_a(x)):.1f}",
                f"{float(schedule.b_a(x)):.1f}",
                f"{dlipm.omega_n:.3f}" if dlipm.is_stable else "unstable",
            )
        )
    pace = (
        f"paced by the servos' acceleration limit {factory.max_acceleration_rad_s2:.3g} rad/s² "
        "(the fastest plan within it, per target)"
        if factory.max_acceleration_rad_s2 is not None
        else f"a fixed time scale {factory.time_scale:.3f}"
    )
    limits = Text(
        f"Gain-scheduled DLIPM (paper A Fig. 19) on the identified error model, ζ = "
        f"{factory.zeta:g}, mass {factory.mass_kg:g} kg, lean length {factory.lean_length_m:.4f} "
        f"m, every {1e3 * factory.settings()['control_period_s']:g} ms; {pace}. Limits: lean "
        f"angle ±{factory.angle_limit_rad:.4f} rad, rate {factory.rate_limit_rad_s:.3g} rad/s, "
        f"targets clamped to the support polygon {factory.support_polygon[0]:.4f} … "
        f"{factory.support_polygon[1]:.4f} m. The linear correction instead leans to "
        "asin(u/l) with u from the fitted slope alone."
    )
    blocks: list[Block] = [limits]
    feedback = plane.factories.get("dlipm_fb")
    if feedback is not None:
        g = feedback.feedback_gains()
        blocks.append(
            Text(
                "DLIPM+feedback: the same DLIPM plus a PI on the measured ZMP (low-passed, "
                f"τ_f = {g.filter_time_constant_s:.3g} s), K_p = {g.kp_rad_per_m:.4g} rad/m, "
                f"K_i = {g.ki_rad_per_m_s:.4g} rad/(m·s), integral and correction clamped to "
                f"±{g.output_limit_rad:.4f} rad, conditional integration as anti-windup, "
                "gains from the identified DC gain and √(g/l) "
                "(`zmpkit.control.dlipm_feedback`). LIPM+PID: the LIPM angle with the same PI."
            )
        )
    table = Table(
        ("ZMP target [m]", "command u = f⁻¹(x) [m]", "steady angle [rad]", "DC gain K [rad/m]",
         "k_a [N]", "B_a [N·s]", "ω_n [rad/s]"),
        tuple(rows),
        "The DLIPM's schedule per target: the command that puts the measured ZMP on the "
        "target, and the gains of eq. 11 (mass explicit).",
        "† outside the fitted range: the schedule extrapolates the error model there.",
    )  # fmt: skip
    return (*blocks, table)


_TABLE1_COLUMNS = (
    ("lipm", "zmp_measured", ".5f", "LIPM ZMP [m]"),
    ("lipm", "error_pct", ".1f", "LIPM error [%]"),
    ("lipm", "error_mm", ".2f", "LIPM error [mm]"),
    ("dlipm", "zmp_measured", ".5f", "DLIPM ZMP [m]"),
    ("dlipm", "error_pct", ".1f", "DLIPM error [%]"),
    ("dlipm", "error_mm", ".2f", "DLIPM error [mm]"),
    ("linear", "error_pct", ".1f", "linear error [%]"),
    ("lipm", "overshoot_pct", ".1f", "LIPM overshoot [%]"),
    ("dlipm", "overshoot_pct", ".1f", "DLIPM overshoot [%]"),
    ("lipm", "settling_time_s", ".2f", "LIPM settling 5 % [s]"),
    ("dlipm", "settling_time_s", ".2f", "DLIPM settling 5 % [s]"),
)
_FEEDBACK_TABLE1_COLUMNS = (
    ("lipm_pid", "error_pct", ".1f", "LIPM+PID error [%]"),
    ("dlipm_fb", "zmp_measured", ".5f", "DLIPM+fb ZMP [m]"),
    ("dlipm_fb", "error_pct", ".1f", "DLIPM+fb error [%]"),
    ("dlipm_fb", "overshoot_pct", ".1f", "DLIPM+fb overshoot [%]"),
    ("dlipm_fb", "settling_time_s", ".2f", "DLIPM+fb settling 5 % [s]"),
)


def table1_table(rows: Sequence[Table1Row]) -> Table:
    """Paper A's Table 1 of one plane, each empty cell marked with why it is empty."""
    notes: list[str] = []
    body = []
    feedback = any(row.dlipm_fb is not None for row in rows)
    columns = _TABLE1_COLUMNS + (_FEEDBACK_TABLE1_COLUMNS if feedback else ())
    for row in rows:
        mark = (" *" if row.fitted_on else "") + (" †" if row.extrapolated else "")
        cells = [f"{row.zmp_ref:g}{mark}"]
        for controller, attribute, spec, _ in columns:
            outcome = row.outcomes()[controller]
            value = getattr(outcome, attribute)
            if value is not None:
                cells.append(f"{value:{spec}}")
                continue
            reason = _why_empty(outcome, row.zmp_ref, attribute)
            if reason not in notes:
                notes.append(reason)
            cells.append(f"– ({notes.index(reason) + 1})")
        body.append(tuple(cells))
    legend = "".join(f"({k}) {reason}  \n" for k, reason in enumerate(notes, start=1))
    return Table(
        ("ZMP_ref [m]", *(header for *_, header in columns)),
        tuple(body),
        "Table 1 (paper A): the settled force–torque ZMP and its error under each controller.",
        "\\* fitted target (its LIPM step was used in the fit); unmarked targets are held out. "
        "† outside the range the error model was fitted on: the controllers extrapolate it.  \n"
        + legend,
    )


def _why_empty(outcome: ControllerOutcome, target_m: float, attribute: str) -> str:
    name = _NAMES.get(outcome.controller, outcome.controller)
    if not outcome.steady.settled:
        return f"{name} at {target_m:g} m {outcome.unsettled_text()}"
    if target_m == 0.0 and attribute != "zmp_measured":
        return "target 0 m: an error or step metric relative to a zero step is undefined"
    value = outcome.steady.value
    stepped = value is not None and step_stands_out(outcome.trial, value)
    if attribute in ("overshoot_pct", "settling_time_s") and not stepped:
        return (
            f"{name} at {target_m:g} m: the measured step is within "
            f"{MIN_STEP_NOISE_RATIO:g} σ of the ZMP's noise, too small to time or to overshoot"
        )
    if attribute == "settling_time_s":
        return f"{name} at {target_m:g} m: did not stay within ±5 % of the step before the end"
    return f"{name} at {target_m:g} m: undefined (the response never reached its settled value)"


def _data_section() -> Section:
    return Section(
        "Data",
        (
            Text(
                "`table1.csv` (Table 1 with every column, empty where undefined), "
                "`params.yaml` (the identified DLIPM parameters per plane), and every trial's "
                "recorded sensors under `datasets/` (read them with "
                "`zmpkit.experiments.read_step_dataset`)."
            ),
        ),
    )


_CAPTIONS = {
    "fig16": "Identification ({plane}): the settled force–torque ZMP x_FT [m] of each LIPM step "
    "against the commanded ZMP x_cmd [m], with the fitted error model (left), and the error "
    "x_FT − x_cmd [mm] (right); paper A Fig. 16. Filled: identification trials the model was "
    "fitted on; open squares: the validation LIPM trials at targets the fit did not use; red ×: "
    "trials that did not settle, left out of the fit, at the mean of their last second.",
    "fig20": "Measured ZMP [m] against the reference [m] under each controller ({plane}); the "
    "shaded region lies outside the fitted range, where the controllers extrapolate; × marks "
    "a trial that did not settle, at the mean of its last second (paper A Fig. 20).",
    "fig21": "Step responses of the measured ZMP [m] over time after the step [s] for each target "
    "(one colour per target, dashed: the target) under the LIPM and the DLIPM, and both at one "
    "target ({plane}, paper A Fig. 21); a red × ends a trial that did not settle, with its "
    "status in the legend.",
    "fig18": "Planned ankle lean [rad] over time [s] for the {target} ZMP step under the DLIPM and "
    "the linear correction, before the servo limits ({plane}; paper A Fig. 18 at 0.09 m).",
}


def balance_figures(
    paths: Sequence[Path], planned_targets_m: Mapping[str, float] | None = None
) -> tuple[Figure, ...]:
    """The balance figures with their captions (by the paper's figure number in the name).

    ``planned_targets_m``: plane → the ZMP step of its planned-lean figure [m].
    """
    figures = []
    for path in paths:
        key, _, rest = path.stem.partition("_")
        plane = rest.split("_")[0]
        template = _CAPTIONS.get(key, "{plane}: " + path.stem.replace("_", " ") + ".")
        planned = (planned_targets_m or {}).get(plane)
        target = "largest" if planned is None else f"{planned:g} m"
        figures.append(Figure(path, template.format(plane=plane, target=target)))
    return tuple(figures)
