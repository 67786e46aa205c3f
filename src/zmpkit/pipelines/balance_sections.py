"""A plane's sections of the ``zmpkit balance`` report: identification, controller, Table 1.

Empty cells of Table 1 carry a mark whose note says why (a trial that did not settle, a
step that does not stand out of the noise).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from zmpkit.analysis.balance_validation import (
    MIN_STEP_NOISE_RATIO,
    ControllerOutcome,
    step_stands_out,
)
from zmpkit.analysis.report_document import Block, Table, Text
from zmpkit.analysis.table1 import Table1Row
from zmpkit.identify import TERMS
from zmpkit.identify.error_model import COEFFICIENT_UNITS
from zmpkit.identify.params import PlaneIdentification
from zmpkit.pipelines.balance import PlaneResult

__all__ = ["controller_blocks", "identification_blocks", "table1_table"]


_NAMES = {
    "lipm": "LIPM",
    "dlipm": "DLIPM",
    "linear": "linear",
    "lipm_pid": "LIPM+PID",
    "dlipm_fb": "DLIPM+feedback",
}


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
