"""The report of ``zmpkit identify sim``: the fitted simulator, how well it reproduces the data.

The targets of a simulator fit (paper B §II) are that the fitted simulator reproduces each
recorded experiment: its trunk-oscillation peak within
:data:`~zmpkit.simfit.validation.FREQUENCY_TOLERANCE_HZ` and its amplitude within
:data:`~zmpkit.simfit.validation.AMPLITUDE_TOLERANCE`, on the fitted experiments and — what
counts — on held-out ones; and that the data pin each fitted parameter down. With
``--self-test`` the hidden truth is known, and the recovery error of each parameter is stated.
"""

from __future__ import annotations

import math

from zmpkit.analysis.provenance import capture_run
from zmpkit.analysis.report_document import Check, Figure, ReportDocument, Section, Table, Text
from zmpkit.pipelines.identify_sim import IdentifySimResult
from zmpkit.simfit.least_squares_refit import refinement_line
from zmpkit.simfit.log_experiment import shooting_summary
from zmpkit.simfit.refit_intervals import ParameterInterval
from zmpkit.simfit.validation import AMPLITUDE_TOLERANCE, FREQUENCY_TOLERANCE_HZ, ReproductionCheck

__all__ = ["identify_sim_document"]


def _reproduction(check: ReproductionCheck, role: str) -> Check:
    detail = (
        f"peak {check.simulated_peak_hz:.2f} Hz against {check.recorded_peak_hz:.2f} Hz "
        f"recorded (|Δ| ≤ {FREQUENCY_TOLERANCE_HZ:g} Hz), amplitude "
        f"{check.simulated_amplitude_rad:.4f} rad against {check.recorded_amplitude_rad:.4f} rad "
        f"(±{100 * AMPLITUDE_TOLERANCE:.0f} %)"
    )
    name = f"{role} `{check.experiment}` reproduced"
    if math.isnan(check.amplitude_error):  # the rollout fell short of the recording
        return Check(name, "undefined", "the simulated rollout fell short of the recording")
    return Check(name, "met" if check.passed else "missed", detail)


def identify_sim_document(result: IdentifySimResult) -> ReportDocument:
    """The fit's report: reproduction per experiment, parameters, identifiability, figures."""
    c = result.config
    blocks: list[Table] = [_parameters_table(result)]
    if result.sloppy_directions:
        blocks.append(_sloppy_table(result))
    if result.recovery:
        blocks.append(_recovery_table(result))
    figures = [
        Figure(path, _caption(role))
        for role, path in result.files.items()
        if path.suffix.lower() == ".png"
    ]
    title = c.robot.title
    return ReportDocument(
        title=f"zmpkit identify sim: the virtual {title}'s simulator fitted to recorded data",
        summary=_summary(result),
        checks=_checks(result),
        sections=(
            Section("Fitted parameters", tuple(blocks)),
            Section("Figures", tuple(figures)),
            _data_section(result),
        ),
        provenance=capture_run(
            c,
            result.started_s,
            (
                ("backend", c.backend),
                ("generations", str(len(result.cma.history))),
                ("runs (population x generations)", _runs(result)),
            ),
        ),
    )


def _runs(result: IdentifySimResult) -> str:
    """Each CMA-ES run's population and generations, e.g. ``"256 x 10, 512 x 9"``."""
    runs: dict[int, list[int]] = {}
    for record in result.cma.history:
        runs.setdefault(record.restart, []).append(record.popsize)
    return ", ".join(f"{sizes[0]} x {len(sizes)}" for sizes in runs.values())


def _checks(result: IdentifySimResult) -> tuple[Check, ...]:
    """Each experiment reproduced, each parameter pinned down, the model adequate."""
    checks = [_reproduction(k, "fitted experiment") for k in result.fit_checks]
    checks += [_reproduction(k, "held-out experiment") for k in result.held_out_checks]
    checks += [
        Check(
            f"`{i.name}` pinned down by the data",
            "met" if i.identifiable else "missed",
            f"cost rises visibly at ±{_pct(i.marginal_resolution)} with the other "
            f"parameters free (±{_pct(i.resolution)} with them held), "
            + (
                f"CMA-ES spread {_pct(i.cma_relative_std)}"
                if not math.isnan(i.cma_relative_std)
                else "refined by Levenberg–Marquardt (no CMA-ES spread)"
            ),
        )
        for i in result.identifiability
    ]
    if result.refinement is not None:
        checks.append(
            Check("refined by Levenberg–Marquardt", "info", refinement_line(result.refinement))
        )
    adequacy = result.adequacy
    if adequacy is not None:
        explains = adequacy.explains
        name = "the model explains the data"
        if explains is None:
            checks.append(Check(name, "undefined", adequacy.verdict))
        else:
            checks.append(Check(name, "met" if explains else "missed", adequacy.verdict))
    return tuple(checks)


def _summary(result: IdentifySimResult) -> str:
    c, adequacy = result.config, result.adequacy
    data = ", ".join(c.data) or "experiments recorded by the self-test"
    return (
        f"CMA-ES fit of the {c.effects} effects' parameters (paper B §II) to {data}, "
        f"reading only commanded angles, encoders, F-T ZMP and IMU; held out: "
        f"{', '.join(c.held_out) or 'none'}; simulated effects "
        f"{result.sim_effects or c.sim_effects}."
        + (f" {shooting}" if (shooting := shooting_summary(result.problem.experiments)) else "")
        + ("" if adequacy is None else f" Verdict: {adequacy.verdict}.")
    )


def _parameters_table(result: IdentifySimResult) -> Table:
    """Each fitted parameter with its unit, noise interval, bounds and identifiability."""
    adequacy = result.adequacy
    precise = adequacy is None or adequacy.explains is not False
    intervals = {i.name: i for i in result.intervals}
    return Table(
        ("parameter", "fitted", "unit", "95 % interval", "bounds", "identifiable", "why"),
        tuple(
            (
                p.name,
                f"{result.fitted[p.name]:.5g}",
                p.unit,
                _interval(intervals.get(p.name)),
                f"{p.lower:.4g} … {p.upper:.4g}",
                "yes" if i.identifiable else "no",
                i.reason,
            )
            for p, i in zip(result.parameters, result.identifiability, strict=True)
        ),
        f"The fitted parameters (best cost {result.cost:.4g})."
        + (f" The 95 % intervals: {result.intervals[0].method}." if result.intervals else "")
        + (
            ""
            if precise
            else " The model does not explain the data: the intervals and resolutions say how "
            "the misfit moves, not how precisely the robot's values are known."
        ),
    )


def _recovery_table(result: IdentifySimResult) -> Table:
    """Self-test: the hidden truth against the fit, per parameter."""
    units = {p.name: p.unit for p in result.parameters}
    return Table(
        ("parameter", "hidden truth", "fitted", "unit", "error [%]"),
        tuple(
            (
                r.parameter,
                f"{r.truth:.5g}",
                f"{r.fitted:.5g}",
                units.get(r.parameter, ""),
                f"{r.error_pct:+.1f}",
            )
            for r in result.recovery
        ),
        "Self-test: the hidden truth of the recorded robot against the fit (the truth "
        "is read only here, to judge the fit).",
    )


def _data_section(result: IdentifySimResult) -> Section:
    return Section(
        "Data",
        (
            Text(
                "`fitted_truth.yaml` (usable as `--truth`), `fitted_parameters.yaml`, "
                "`cost_history.csv`, `identifiability.csv`, `sloppy_directions.csv`, "
                "`reproduction.csv`"
                + (", `recovery.csv`" if result.recovery else "")
                + "; the checkpoint resumes an interrupted fit (`--resume`)."
            ),
        ),
    )


def _interval(interval: ParameterInterval | None) -> str:
    if interval is None or not math.isfinite(interval.half_width):
        return "not measured"
    text = f"{interval.lower:.5g} … {interval.upper:.5g} (±{_pct(interval.half_width)}"
    if math.isfinite(interval.bias):
        text += f" about {interval.corrected:.5g}, estimator bias {100 * interval.bias:+.2g} %"
    return text + ")"


def _pct(fraction: float) -> str:
    return f"{100 * fraction:.1f} %" if math.isfinite(fraction) else "> 100 %"


def _sloppy_table(result: IdentifySimResult) -> Table:
    """The combinations of parameters the data leave loose (relative moves)."""
    return Table(
        ("direction", "cost rises visibly at", "components (relative moves)"),
        tuple(
            (
                str(k + 1),
                f"±{_pct(d.resolution)}",
                ", ".join(f"{name} {value:+.2f}" for name, value in d.components),
            )
            for k, d in enumerate(result.sloppy_directions)
        ),
        "Combinations of the parameters' relative changes along which the fit's cost hardly "
        "rises (the cost's Hessian at the fit, loosest first): the data pin these down "
        "more coarsely than 10 %.",
    )


def _caption(role: str) -> str:
    if role == "cost_plot":
        return "Best and mean cost [-] per CMA-ES generation."
    name = role.removeprefix("fit_")
    return (
        f"Experiment `{name}`: recorded and simulated signals with the fitted parameters "
        "(trunk tilt [rad], joint angles [rad])."
    )
