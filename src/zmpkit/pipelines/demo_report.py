"""The text of ``zmpkit demo``'s ``report.md``: one section per part of the demo."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from zmpkit.models import Dlipm
from zmpkit.robots.registry import get_robot

__all__ = ["LABELS", "format_optional", "write_report"]


LABELS = {
    "lipm": "LIPM (k_a = B_a = 0): unstable",
    "dlipm_si": "DLIPM, ζ = 0.8, DC gain 1/l (SI, θ in rad)",
    "dlipm_paper_units": "DLIPM, ζ = 0.8, ω_n = 0.438 (paper A, θ in deg)",
}


def format_optional(x: float | None) -> str:
    """Format ``x`` with 6 significant digits, or an empty string for None (a table cell)."""
    return "" if x is None else f"{x:.6g}"


def write_report(
    out: Path,
    config: Any,
    models: dict[str, Dlipm],
    metrics,
    figures,
    balance: Any,
    walks: dict[str, Any],
    compensation: dict[str, Any] | None,
    videos: Sequence[Path] = (),
) -> Path:
    """Write the demo's ``report.md`` into ``out`` and return its path.

    Args:
        out: the demo's output folder; linked files are relative to it.
        config: the demo's :class:`~zmpkit.pipelines.demo.DemoConfig` (mass [kg], length [m],
            ZMP step [m], damping ratio ζ [-]).
        models: the demo's models by key of :data:`LABELS`.
        metrics: step-response metrics of each stable model, by key of :data:`LABELS`.
        figures: the figures the demo wrote (the report links them by their fixed names).
        balance: the quick balance run's :class:`BalanceArtifacts`, or None.
        walks: the walking robot's walk summaries by effect set (empty without walking).
        compensation: the walk compensation's ``summary.json`` contents, or None.
        videos: the videos the demo wrote (linked relative to ``out``).

    Returns:
        The path of ``report.md``.
    """
    si, paper = models["dlipm_si"], models["dlipm_paper_units"]
    rows = "\n".join(
        f"| {LABELS[n]} | {format_optional(m.overshoot_pct)} | {format_optional(m.rise_time_s)} | "
        f"{format_optional(m.settling_time_s)} | {format_optional(math.degrees(m.final_value))} |"
        for n, m in metrics.items()
    )
    robot = _title(config.balance_robot)
    sections = _balance_section(out, balance, config) + _walk_section(walks, config)
    text = f"""# zmpkit demo

## LIPM vs DLIPM angular step response (paper A §4.4, Fig. 17–18)

Pendulum: m = {config.mass_kg} kg, l = {config.length_m} m ({robot}'s balance model, paper A
§4.1). ZMP step x_ref = {config.zmp_step_m} m; the LIPM's static ankle angle for it is
asin(x/l) = {math.degrees(math.asin(config.zmp_step_m / config.length_m)):.3f}°.

The DLIPM, with the mass explicit: m l² θ̈ + B_a l θ̇ + (k_a − m g) l θ = m g x_ref, i.e.
Θ(s)/X(s) = γ/(s² + α s + β), γ = g/l², α = B_a/(m l), β = (k_a − m g)/(m l).
With k_a = B_a = 0 it is the LIPM, whose pole at +√(g/l) makes the response diverge.

![Fig. 17](fig17_lipm_vs_dlipm.png)

Designed for ζ = {config.zeta} with the DC gain of the linearised LIPM (1/l [rad/m]):
k_a = {si.k_a:.1f} N, B_a = {si.b_a:.1f} N·s, ω_n = {si.omega_n:.3f} rad/s.

Paper A's design example (ζ = 0.8, ω_n = 0.4376) is the same design with the angle in
**degrees**: √(g/l · π/180) = {paper.omega_n:.4f}. Its code sends θ to the joint in degrees,
so its β is π/180 times the SI one and its response is {si.omega_n / paper.omega_n:.1f}×
slower in time for the same damping ratio.

![Fig. 18](fig18_dlipm_zeta08.png)

| model | overshoot [%] | rise 10–90 % [s] | settling 2 % [s] | final [deg] |
|---|---|---|---|---|
{rows}

Data: `step_metrics.csv`; parameters: `dlipm.yaml`.

{sections}{_compensation_section(compensation)}{_video_line(out, videos)}
## To come

Fitting the simulator to recorded data (MoToFlex's evolutionary identification).
"""
    path = out / "report.md"
    path.write_text(text, encoding="utf-8")
    return path


def _video_line(out: Path, videos: Sequence[Path]) -> str:
    links = ", ".join(f"[{p.relative_to(out).as_posix()}]({p.relative_to(out).as_posix()})"
                      for p in videos)  # fmt: skip
    return f"\nVideos: {links}.\n" if videos else ""


def _title(robot: str) -> str:
    return get_robot(robot).title


def _balance_section(out: Path, balance: Any, config: Any) -> str:
    """``balance`` is the quick balance run's :class:`BalanceArtifacts`, or None."""
    if balance is None:
        return ""
    link = balance.report.relative_to(out).as_posix()
    figures = "".join(
        f"\n**{plane}** plane:\n\n" + "".join(f"- {line}\n" for line in targets.lines())
        for plane, targets in balance.targets.items()
    )
    title = _title(config.balance_robot)
    return f"""## The virtual {title}: LIPM vs scheduled DLIPM (paper A §4.1–4.6, Table 1)

The quick balance pipeline ran on the virtual {title} with every effect on: LIPM step
experiments, identification of the steady-state error model from the force–torque sensors
(fitted on the even targets), the gain-scheduled DLIPM and a single linear correction on
every target, and paper A's Table 1. Against the targets:
{figures}
Its report, with Table 1 and the figures: [{link}]({link}).
"""


_WALK_HEADER = (
    "| effects | fell | speed [m/s] | trunk-pitch peak [Hz] | peak amplitude [rad] "
    "| std [rad] | double-support feet distance [m] |\n" + "|---" * 7 + "|"
)


def _walk_section(walks: dict[str, Any], config: Any) -> str:
    if not walks:
        return ""
    rows = "\n".join(
        f"| {name} | {w.fell} | {w.mean_speed_mps:.4f} | {w.trunk_pitch_peak_hz:.2f} | "
        f"{w.trunk_pitch_peak_amplitude_rad:.4f} | {w.trunk_pitch_std_rad:.4f} | "
        f"{w.mean_double_support_foot_distance_m:.4f} |"
        for name, w in walks.items()
    )
    ratio = (
        walks["all"].trunk_pitch_peak_amplitude_rad / walks["none"].trunk_pitch_peak_amplitude_rad
    )
    robot = _title(config.walk_robot)
    return f"""
## The virtual {robot} walking (paper B §III)

10 s at a commanded 0.2 m/s, 0.5 s steps, 3D-LIPM preview-control pattern, whole-body IK,
played on the virtual {robot} with every effect off (rigid, ideal joints) and on (motor with PID,
inductance, gears with flexibility and backlash, flexible links).

{_WALK_HEADER}
{rows}

With the effects on, the step-frequency oscillation is {ratio:.1f}× the rigid walk's. Figures:
[walk_all/trunk_pitch_spectrum.png](walk_all/trunk_pitch_spectrum.png),
[walk_all/trunk_pitch.png](walk_all/trunk_pitch.png),
[walk_none/trunk_pitch_spectrum.png](walk_none/trunk_pitch_spectrum.png).
"""


def _compensation_section(summary: dict[str, Any] | None) -> str:
    if summary is None:
        return ""
    peak, std = summary["peak_reduction_pct"], summary["std_reduction_pct"]
    figures = (
        "no validation walk where both versions stood"
        if peak is None
        else (
            f"the step-frequency peak is {peak:.1f} % lower and the oscillation's std "
            f"{std:.1f} % lower than without it"
        )
    )
    return f"""
## Compensating the walk (paper B §III.E)

`zmpkit walk compensate --method auto --quick` tuned half-sine, sawtooth and Fourier offsets on
the desired ZMP by CMA-ES over simulated walks and kept the best ({summary["chosen"]}). On
{summary["walks_compared"]} validation walk(s) not used for tuning, {figures}; compensated
walks that fell: {summary["compensated_falls"]}. Report:
[compensate/report.md](compensate/report.md).
"""
