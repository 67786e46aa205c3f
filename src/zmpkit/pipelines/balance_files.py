"""Artefacts of ``zmpkit balance``: params, Table 1, figures and the report (``report.html``)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from zmpkit.analysis.balance_plots import (
    plot_error_fit,
    plot_step_responses_by_target,
    plot_zmp_ref_vs_measured,
)
from zmpkit.analysis.balance_targets import BalanceTargets, balance_targets
from zmpkit.analysis.balance_verdict import PlaneVerdict, plane_verdict
from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.step_plot import Curve, plot_step_responses
from zmpkit.analysis.table1 import Table1Row, write_table1_csv
from zmpkit.experiments import CONTROL_PERIOD_S
from zmpkit.pipelines.balance import BalanceResult, PlaneResult
from zmpkit.pipelines.balance_document import (
    balance_document,
    balance_figures,
    step_trial_videos,
)
from zmpkit.pipelines.balance_video import write_step_trial_video

__all__ = ["BalanceArtifacts", "write_balance"]

PAPER_PLANNED_TARGET_M = 0.09
"""Paper A's planned lean (Fig. 18 and 21b) is for this ZMP step [m]."""


def planned_target_m(rows: Sequence[Table1Row]) -> float:
    """The ZMP step whose planned lean is drawn [m].

    Paper A's 0.09 m where the run reaches it, else the run's largest target (a smaller
    robot's).
    """
    largest = max((abs(r.zmp_ref) for r in rows), default=PAPER_PLANNED_TARGET_M)
    return PAPER_PLANNED_TARGET_M if largest >= PAPER_PLANNED_TARGET_M else largest


_PLANNED_DURATION_S = 15.0


@dataclass(frozen=True)
class BalanceArtifacts:
    """Paths written by :func:`write_balance`, each plane's figures and verdict.

    ``videos`` holds the step trial's video when the config asked for one (``step_trial.mp4``,
    or the GIF or keyframes written instead). ``failed_planes``: plane → why it did not
    finish (its bars are undefined).
    """

    report: Path
    table1: Path
    params: Path
    figures: tuple[Path, ...]
    targets: dict[str, BalanceTargets]
    verdicts: dict[str, PlaneVerdict]
    videos: tuple[Path, ...] = ()
    failed_planes: dict[str, str] = field(default_factory=dict)

    @property
    def met(self) -> bool:
        """Whether every bar of every plane was met (a failed plane's are not)."""
        return not self.failed_planes and all(v.met for v in self.verdicts.values())


def write_balance(
    result: BalanceResult, out_dir: str | Path, report_format: str = "html"
) -> BalanceArtifacts:
    """Write ``params.yaml`` (+ one per plane), ``table1.csv``, figures and the report.

    Args:
        result: the balance run.
        out_dir: its folder.
        report_format: ``html`` (``report.html``), ``md`` (``report.md``) or ``both``.
    """
    out = Path(out_dir)
    rows = [row for plane in result.planes.values() for row in plane.rows]
    table1 = write_table1_csv(rows, out / "table1.csv")
    params = _write_params(result, out)
    figures: list[Path] = []
    for plane in result.planes.values():
        figures += _plane_figures(plane, out)
    verdicts = {name: plane_verdict(name, plane.rows) for name, plane in result.planes.items()}
    video = write_step_trial_video(result, out) if result.config.video else None
    videos = () if video is None or video.path is None else (video.path,)
    document = balance_document(
        result,
        balance_figures(
            figures, {name: planned_target_m(p.rows) for name, p in result.planes.items()}
        ),
        verdicts,
        videos=step_trial_videos(result, videos),
    )
    report = write_report(document, out, report_format)
    targets = {name: balance_targets(name, plane.rows) for name, plane in result.planes.items()}
    return BalanceArtifacts(
        report, table1, params, tuple(figures), targets, verdicts, videos, result.failed_planes
    )


def _write_params(result: BalanceResult, out: Path) -> Path:
    doc = {}
    for name in result.planes:
        params = result.params(name)
        params.to_yaml(out / f"params_{name}.yaml")
        doc[name] = params.to_dict()
    path = out / "params.yaml"
    header = (
        "# Identified DLIPM parameters per plane (zmpkit balance). com_height_m is the\n"
        "# pendulum length the controller uses: ankle pivot to CoM, from the design model.\n"
        "# params_<plane>.yaml hold the same, one plane each, loadable by BalanceParams.\n"
    )
    path.write_text(header + yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path


def _plane_figures(plane: PlaneResult, out: Path) -> list[Path]:
    name, ident = plane.plane, plane.identification.planes[plane.plane]
    figures = [
        plot_error_fit(ident, plane.rows, out / f"fig16_{name}.png", plane=name),
        plot_zmp_ref_vs_measured(plane.rows, out / f"fig20_{name}.png", plane=name),
        plot_step_responses_by_target(plane.rows, out / f"fig21_{name}.png", plane=name),
        _planned_angles(plane, out / f"fig18_{name}_planned_angle.png"),
    ]
    return figures


def _planned_angles(plane: PlaneResult, path: Path) -> Path:
    """The ankle-angle plans of the scheduled DLIPM and the linear correction at one target."""
    target = planned_target_m(plane.rows)
    n = round(_PLANNED_DURATION_S / CONTROL_PERIOD_S)
    t = np.arange(n + 1, dtype=np.float64) * CONTROL_PERIOD_S
    curves = []
    for kind, factory in plane.factories.items():
        controller = factory()
        controller.set_target(target)
        angles = np.array([0.0] + [controller.step() for _ in range(n)])
        curves.append(Curve(f"{kind} plan (before the servo limits)", t, angles))
    lipm = math.asin(target / plane.lean_length_m)
    return plot_step_responses(
        curves,
        path,
        title=f"Planned lean for a {target:g} m ZMP step, {plane.plane}",
        reference_rad=lipm,
    )
