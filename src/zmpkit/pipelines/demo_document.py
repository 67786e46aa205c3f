"""The report of ``zmpkit demo``: the model, the balance robot, the walking robot, compensation.

The demo's verdict gathers the targets of its parts: the DLIPM's step response against the
second-order closed form (the model is right), paper A's bars on the balance robot, whether
each walk stood, and whether the compensation helped on walks it was not tuned on. Each part
also writes its own report (linked at the top); the demo's page shows the figures a reader
needs to judge each part without opening them (:mod:`zmpkit.pipelines.demo_sections`).
"""

from __future__ import annotations

import math
from pathlib import Path

from zmpkit.analysis.provenance import capture_described
from zmpkit.analysis.report_document import Check, ReportDocument, Section, Text, Video
from zmpkit.pipelines.balance_checks import balance_checks
from zmpkit.pipelines.demo_config import DemoConfig
from zmpkit.pipelines.demo_sections import (
    LABELS,
    DemoParts,
    balance_section,
    data_section,
    model_section,
    simfit_section,
    time_section,
    walk_section,
)
from zmpkit.pipelines.walk_compensate import CompensateResult
from zmpkit.pipelines.walk_compensate_document import compensation_checks, compensation_sections
from zmpkit.pipelines.walk_document import effects_name, walk_checks

__all__ = [
    "LABELS",
    "DemoParts",
    "demo_document",
    "format_optional",
    "walk_side_by_side_videos",
]

OVERSHOOT_TOLERANCE_PCT = 0.01
"""How close the simulated overshoot must come to the closed form [percentage points]."""


def format_optional(x: float | None) -> str:
    """Format ``x`` with 6 significant digits, or an empty string for None (a table cell)."""
    return "" if x is None else f"{x:.6g}"


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


def demo_document(config: DemoConfig, parts: DemoParts) -> ReportDocument:
    """The demo's report: the verdict of every part, then one section per part."""
    checks = list(_model_checks(config, parts))
    sections = [model_section(config, parts)]
    links: list[tuple[str, Path]] = []
    if parts.balance is not None:
        artifacts, result = parts.balance
        checks += [c.prefixed("balance") for c in balance_checks(result, artifacts.verdicts)]
        sections.append(balance_section(config, artifacts, result, parts.balance_videos))
        links.append(("balance", artifacts.report))
    if parts.walks:
        for effects, walk in parts.walks.items():
            name = f"walk, {effects_name(effects)}"
            stood, stepped = walk_checks(walk.summary)[:2]  # the metrics are in the table
            checks += [stood.prefixed(name), stepped.prefixed(name)]
            if "report" in walk.files:
                links.append((name, walk.files["report"]))
        sections.append(walk_section(config, parts))
    if parts.compensation is not None:
        comp = parts.compensation
        checks += [c.prefixed("compensation") for c in compensation_checks(comp)]
        sections.append(_compensation_section(comp))
        if "report" in comp.files:
            links.append(("compensation", comp.files["report"]))
    sections += [simfit_section(), data_section()]
    if parts.part_times_s:
        sections.append(time_section(parts.part_times_s))
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


def _compensation_section(comp: CompensateResult) -> Section:
    """The compensation run: what was tuned, then its validation table and figures."""
    figures = {k: p for k, p in comp.files.items() if p.suffix == ".png"}
    return Section(
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


def _summary(config: DemoConfig) -> str:
    balance = config.balance_robot.title
    walking = config.walk_robot.title
    return (
        f"The main job on the built-in virtual robots: the LIPM and the Dynamic LIPM as models "
        f"(paper A §4.4), then paper A's balance experiment on the virtual {balance} (LIPM "
        "steps, identification from the force–torque sensors, gain-scheduled DLIPM, Table 1), "
        f"then paper B's walk on the virtual {walking} with every effect off and on, and the "
        "compensation of its trunk oscillation judged on walks it was not tuned on."
    )


def _model_checks(config: DemoConfig, parts: DemoParts) -> tuple[Check, ...]:
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
