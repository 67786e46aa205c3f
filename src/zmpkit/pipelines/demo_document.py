"""The report of ``zmpkit demo``: the model, the balance robot, the walking robot, compensation.

The demo's verdict gathers the targets of its parts: the DLIPM's step response against the
second-order closed form (the model is right), paper A's bars on the balance robot, whether
each walk stood, and whether the compensation helped on walks it was not tuned on. Each part
also writes its own report (linked at the top); the demo's page shows the figures a reader
needs to judge each part without opening them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from zmpkit.analysis.provenance import capture_described
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
from zmpkit.models import Dlipm
from zmpkit.pipelines.balance_checks import balance_checks
from zmpkit.pipelines.balance_document import balance_figures
from zmpkit.pipelines.balance_files import BalanceArtifacts
from zmpkit.pipelines.balance_sections import table1_table
from zmpkit.pipelines.walk import WalkResult
from zmpkit.pipelines.walk_compensate import CompensateResult
from zmpkit.pipelines.walk_compensate_document import compensation_checks, compensation_sections
from zmpkit.pipelines.walk_document import effects_name, walk_checks, walk_metrics_table
from zmpkit.signals.step_metrics import StepMetrics

__all__ = [
    "LABELS",
    "DemoParts",
    "demo_document",
    "format_optional",
    "walk_side_by_side_videos",
]

LABELS = {
    "lipm": "LIPM (k_a = B_a = 0): unstable",
    "dlipm_si": "DLIPM, ζ = 0.8, DC gain 1/l (SI, θ in rad)",
    "dlipm_paper_units": "DLIPM, ζ = 0.8, ω_n = 0.438 (paper A, θ in deg)",
}
OVERSHOOT_TOLERANCE_PCT = 0.01
"""How close the simulated overshoot must come to the closed form [percentage points]."""


def format_optional(x: float | None) -> str:
    """Format ``x`` with 6 significant digits, or an empty string for None (a table cell)."""
    return "" if x is None else f"{x:.6g}"


@dataclass(frozen=True)
class DemoParts:
    """What the demo ran, for its report.

    Attributes:
        models: the pendulum models by key of :data:`LABELS`.
        metrics: step-response metrics of each stable model.
        figures: the model figures (Fig. 17 and 18 of paper A).
        balance: the balance run's artefacts and result, or None.
        walks: the walks by effect set (``none``, ``all``); empty without walking.
        compensation: the compensation run, or None.
        videos: videos of the walks, each with its caption.
        balance_videos: videos of the balance robot, each with its caption.
        extra_figures: further figures with their captions (e.g. rigid vs all effects).
        started_s: when the demo started [s since the epoch].
        part_times_s: wall time of each part, in the order they ran [s].
    """

    models: Mapping[str, Dlipm]
    metrics: Mapping[str, StepMetrics]
    figures: tuple[Path, ...]
    balance: tuple[BalanceArtifacts, Any] | None
    walks: Mapping[str, WalkResult]
    compensation: CompensateResult | None
    videos: tuple[Video, ...] = ()
    balance_videos: tuple[Video, ...] = ()
    extra_figures: tuple[Figure, ...] = ()
    started_s: float = 0.0
    part_times_s: Mapping[str, float] = field(default_factory=dict)


def walk_side_by_side_videos(paths: tuple[Path, ...]) -> tuple[Video, ...]:
    """The demo's walk video(s), captioned."""
    return tuple(
        Video(
            path,
            "The rigid walk (left) and the walk with every effect on (right), 10 s at 0.2 m/s, "
            "open loop, rendered from the recorded joint angles; the camera follows each "
            "robot's base, the time is simulated time, and a fall would be marked in red.",
        )
        for path in paths
    )


def demo_document(out: Path, config: Any, parts: DemoParts) -> ReportDocument:
    """The demo's report (``config`` is the :class:`~zmpkit.pipelines.demo.DemoConfig`)."""
    checks = list(_model_checks(config, parts))
    sections = [_model_section(config, parts)]
    links: list[tuple[str, Path]] = []
    if parts.balance is not None:
        artifacts, result = parts.balance
        checks += [c.prefixed("balance") for c in balance_checks(result, artifacts.verdicts)]
        sections.append(_balance_section(config, artifacts, result, parts.balance_videos))
        links.append(("balance", artifacts.report))
    if parts.walks:
        for effects, walk in parts.walks.items():
            name = f"walk, {effects_name(effects)}"
            stood, stepped = walk_checks(walk.summary)[:2]  # the metrics are in the table
            checks += [stood.prefixed(name), stepped.prefixed(name)]
            if "report" in walk.files:
                links.append((name, walk.files["report"]))
        sections.append(_walk_section(config, parts))
    if parts.compensation is not None:
        comp = parts.compensation
        checks += [c.prefixed("compensation") for c in compensation_checks(comp)]
        figures = {k: p for k, p in comp.files.items() if p.suffix == ".png"}
        sections.append(
            Section(
                f"Compensating the walk (paper B §IV): `{comp.summary.method}`",
                (
                    Text(
                        "`zmpkit walk compensate --method auto --quick` tuned half-sine, "
                        "sawtooth and Fourier offsets on the desired ZMP by CMA-ES over "
                        f"simulated walks and kept the best ({comp.chosen}); it is judged on "
                        "validation walks that differ from the tuning walks in speed, step "
                        "duration and robot."
                    ),
                ),
                compensation_sections(comp, figures),
            )
        )
        if "report" in comp.files:
            links.append(("compensation", comp.files["report"]))
    sections += [_simfit_section(), _data_section()]
    if parts.part_times_s:
        sections.append(_time_section(parts.part_times_s))
    return ReportDocument(
        title="zmpkit demo: the LIPM and the robot that really moves",
        summary=_summary(config),
        checks=tuple(checks),
        sections=tuple(sections),
        provenance=capture_described(
            robot=f"{config.balance_robot.source} (balance), {config.walk_robot.source} (walking)",
            started_s=parts.started_s,
            effects="none and all",
            seed=0,
        ),
        parts=tuple(links),
    )


def _summary(config: Any) -> str:
    balance = config.balance_robot.title
    walking = config.walk_robot.title
    return (
        f"The main job on the built-in virtual robots: the LIPM and the Dynamic LIPM as models "
        f"(paper A §4.4), then paper A's balance experiment on the virtual {balance} (LIPM "
        "steps, identification from the force–torque sensors, gain-scheduled DLIPM, Table 1), "
        f"then paper B's walk on the virtual {walking} with every effect off and on, and the "
        "compensation of its trunk oscillation judged on walks it was not tuned on."
    )


def _model_checks(config: Any, parts: DemoParts) -> tuple[Check, ...]:
    zeta = config.zeta
    closed_form = 100.0 * math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta**2))
    checks = []
    for name in ("dlipm_si", "dlipm_paper_units"):
        overshoot = parts.metrics[name].overshoot_pct if name in parts.metrics else None
        if overshoot is None:
            checks.append(Check(f"model: {name} overshoot", "undefined", "no overshoot measured"))
            continue
        gap = abs(overshoot - closed_form)
        checks.append(
            Check(
                f"model: {LABELS[name]} step response against the closed form",
                "met" if gap <= OVERSHOOT_TOLERANCE_PCT else "missed",
                f"overshoot {overshoot:.4f} % against exp(−πζ/√(1−ζ²)) = {closed_form:.4f} % "
                f"(|Δ| ≤ {OVERSHOOT_TOLERANCE_PCT} points)",
            )
        )
    return tuple(checks)


def _model_section(config: Any, parts: DemoParts) -> Section:
    si, paper = parts.models["dlipm_si"], parts.models["dlipm_paper_units"]
    lipm_static = math.degrees(math.asin(config.zmp_step_m / config.length_m))
    rows = tuple(
        (
            LABELS[n],
            _opt(m.overshoot_pct, ".3f"),
            _opt(m.rise_time_s, ".3f"),
            _opt(m.settling_time_s, ".3f"),
            _opt(m.final_value, ".5f"),
        )
        for n, m in parts.metrics.items()
    )
    fig17, fig18 = parts.figures
    text = Text(
        f"Pendulum: m = {config.mass_kg:g} kg, l = {config.length_m:g} m (the balance robot's "
        f"model, paper A §4.1); ZMP step x_ref = {config.zmp_step_m:g} m, for which the LIPM's "
        f"static ankle angle is asin(x/l) = {math.radians(lipm_static):.4f} rad.\n\n"
        "The DLIPM, with the mass explicit: m l² θ̈ + B_a l θ̇ + (k_a − m g) l θ = m g x_ref, "
        "i.e. Θ(s)/X(s) = γ/(s² + α s + β), γ = g/l², α = B_a/(m l), β = (k_a − m g)/(m l). "
        "With k_a = B_a = 0 it is the LIPM, whose pole at +√(g/l) makes the response diverge.\n\n"
        f"Designed for ζ = {config.zeta:g} with the DC gain of the linearised LIPM (1/l "
        f"[rad/m]): k_a = {si.k_a:.1f} N, B_a = {si.b_a:.1f} N·s, ω_n = {si.omega_n:.3f} rad/s. "
        f"Paper A's design example (ζ = 0.8, ω_n = 0.4376) is the same design with the angle in "
        f"degrees: √(g/l · π/180) = {paper.omega_n:.4f} rad/s; its code sends θ to the joint in "
        f"degrees, so its response is {si.omega_n / paper.omega_n:.1f}× slower for the same "
        "damping ratio."
    )
    return Section(
        "The model: LIPM and DLIPM step responses (paper A §4.4)",
        (
            text,
            Figure(
                fig17,
                f"Ankle angle [rad] after a {config.zmp_step_m:g} m ZMP step over time [s]: the "
                "LIPM diverges, the DLIPM settles at the linearised LIPM angle x/l (dashed: the "
                "LIPM's static angle asin(x/l)); paper A Fig. 17.",
            ),
            Figure(
                fig18,
                "The DLIPM designed for ζ = 0.8: in SI units (θ in rad) and with paper A's "
                "degree-unit gains, both in rad, over time [s] (paper A Fig. 18).",
            ),
            Table(
                ("model", "overshoot [%]", "rise 10–90 % [s]", "settling 2 % [s]", "final [rad]"),
                rows,
                "Step metrics of the stable models (the LIPM has none: it diverges).",
            ),
        ),
    )


def _opt(value: float | None, spec: str) -> str:
    return "–" if value is None else f"{value:{spec}}"


def _balance_section(
    config: Any, artifacts: BalanceArtifacts, result: Any, videos: tuple[Video, ...]
) -> Section:
    title = config.balance_robot.title
    blocks: list[Block] = [
        Text(
            f"`zmpkit balance --quick` on the virtual {title} with every effect on: LIPM step "
            "experiments, identification of the steady-state error model from the force–torque "
            "sensors, the gain-scheduled DLIPM and a single linear correction on every target. "
            "Its own report has the identification and every figure."
        )
    ]
    figures = {f.path.name: f for f in balance_figures(artifacts.figures)}
    for name, plane in result.planes.items():
        blocks.append(table1_table(plane.rows))
        key = f"fig20_{name}.png"
        if key in figures:
            blocks.append(figures[key])
    blocks += list(videos)
    return Section(
        f"The virtual {title}'s balance: LIPM vs scheduled DLIPM (paper A §4)", tuple(blocks)
    )


def _walk_section(config: Any, parts: DemoParts) -> Section:
    title = config.walk_robot.title
    walks = parts.walks
    summaries = {effects_name(k): w.summary for k, w in walks.items()}
    blocks: list[Block] = [
        Text(
            "10 s at a commanded 0.2 m/s with 0.5 s steps: 3D-LIPM preview-control pattern, "
            f"whole-body IK, played open loop on the virtual {title} with every effect off "
            "(rigid, ideal joints) and on (motor with PID, inductance, gears with flexibility "
            "and backlash, flexible links), as in paper B §III."
        ),
        walk_metrics_table(summaries, "The rigid walk against the walk with every effect on."),
    ]
    rigid, full = walks.get("none"), walks.get("all")
    if rigid is not None and full is not None:
        a = rigid.summary.trunk_pitch_peak_amplitude_rad
        b = full.summary.trunk_pitch_peak_amplitude_rad
        if a and b is not None:
            blocks.append(
                Text(
                    f"With every effect on, the trunk's step-frequency oscillation is "
                    f"{b / a:.1f}× the rigid walk's (paper B Fig. 6 attributes it to the motor "
                    "and its PID)."
                )
            )
    blocks += list(parts.extra_figures)
    for effects, walk in walks.items():
        spectrum = walk.files.get("spectrum")
        if spectrum is not None:
            window = walk.summary.window_s
            blocks.append(
                Figure(
                    spectrum,
                    f"Trunk-pitch amplitude spectrum [rad], {effects_name(effects)}, over the "
                    f"steady window {window[0]:.2f}–{window[1]:.2f} s (the summary's); the step "
                    "frequency is marked.",
                )
            )
    blocks += list(parts.videos)
    return Section(f"The virtual {title} walking (paper B §III)", tuple(blocks))


def _simfit_section() -> Section:
    return Section(
        "Fitting the simulator to recorded data (paper B §II)",
        (
            Text(
                "Not run in the demo, for time: `zmpkit identify sim` fits the simulator's "
                "effect parameters (motor, gears, flexibility, mass) to recorded walks or step "
                "datasets by CMA-ES, and checks the fit on held-out experiments. Try it on a "
                "virtual robot whose truth it does not read: `zmpkit identify sim --self-test "
                "--quick --out out/fit` (records experiments from a perturbed robot, fits them, "
                "and writes `recovery.csv` with the fitted against the hidden values)."
            ),
        ),
    )


def _data_section() -> Section:
    return Section(
        "Data",
        (
            Text(
                "`step_metrics.csv` and `dlipm.yaml` (the model); `balance/` (Table 1, "
                "parameters, datasets); `walk_none/`, `walk_all/` (summaries and time series); "
                "`compensate/` (summary and tuning)."
            ),
        ),
    )


def _time_section(times_s: Mapping[str, float]) -> Section:
    """Where the demo's wall time went, part by part."""
    total_s = sum(times_s.values())
    rows = tuple(
        (part, f"{t_s:.1f}", f"{100.0 * t_s / total_s:.0f}" if total_s > 0 else "")
        for part, t_s in times_s.items()
    )
    table = Table(
        ("part", "wall time [s]", "share [%]"),
        (*rows, ("total", f"{total_s:.1f}", "100")),
        "Wall time of each part of this demo run, measured on this machine (the balance "
        "part includes its step-trial video). The balance and compensation parts run their "
        "simulations on two worker processes.",
    )
    return Section("Where the time went", (table,))
