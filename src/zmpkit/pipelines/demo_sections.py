"""The sections of ``zmpkit demo``'s report: the model, the balance robot, the walks, the rest.

Each takes the demo's config and what its parts produced (:class:`DemoParts`);
:mod:`zmpkit.pipelines.demo_document` puts them together with the verdict.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit.analysis.report_document import Block, Figure, Section, Table, Text, Video
from zmpkit.models import Dlipm
from zmpkit.pipelines.balance import BalanceResult
from zmpkit.pipelines.balance_document import balance_figures
from zmpkit.pipelines.balance_files import BalanceArtifacts
from zmpkit.pipelines.balance_sections import table1_table
from zmpkit.pipelines.demo_config import DemoConfig
from zmpkit.pipelines.walk import WalkResult
from zmpkit.pipelines.walk_compensate import CompensateResult
from zmpkit.pipelines.walk_document import effects_name, walk_metrics_table
from zmpkit.signals.step_metrics import StepMetrics

__all__ = [
    "LABELS",
    "DemoParts",
    "balance_section",
    "data_section",
    "model_section",
    "simfit_section",
    "time_section",
    "walk_section",
]

LABELS = {
    "lipm": "LIPM (k_a = B_a = 0): unstable",
    "dlipm_si": "DLIPM, ζ = 0.8, DC gain 1/l (SI, θ in rad)",
    "dlipm_paper_units": "DLIPM, ζ = 0.8, ω_n = 0.438 (paper A, θ in deg)",
}


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
    balance: tuple[BalanceArtifacts, BalanceResult] | None
    walks: Mapping[str, WalkResult]
    compensation: CompensateResult | None
    videos: tuple[Video, ...] = ()
    balance_videos: tuple[Video, ...] = ()
    extra_figures: tuple[Figure, ...] = ()
    started_s: float = 0.0
    part_times_s: Mapping[str, float] = field(default_factory=dict)


def model_section(config: DemoConfig, parts: DemoParts) -> Section:
    """The LIPM and DLIPM step responses: the designs, Fig. 17 and 18, their step metrics."""
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


def balance_section(
    config: DemoConfig,
    artifacts: BalanceArtifacts,
    result: BalanceResult,
    videos: tuple[Video, ...],
) -> Section:
    """The balance robot: Table 1 and Fig. 20 of each plane, and its step-trial video."""
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


def walk_section(config: DemoConfig, parts: DemoParts) -> Section:
    """The rigid and the all-effects walk: metrics, comparison, spectra and video."""
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


def simfit_section() -> Section:
    """The simulator fit, not run in the demo: how to try it."""
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


def data_section() -> Section:
    """Where the demo's data files are."""
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


def time_section(times_s: Mapping[str, float]) -> Section:
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
