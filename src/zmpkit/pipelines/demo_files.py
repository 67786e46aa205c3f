"""The files of ``zmpkit demo``: the model's figures and files, the walk comparison, the report.

Fig. 17 and 18 of paper A (``fig17_lipm_vs_dlipm.png``, ``fig18_dlipm_zeta08.png``), the step
metrics of each model (``step_metrics.csv``), the models' parameters (``dlipm.yaml``), the
rigid against the all-effects walk (paper B Fig. 6) and the demo's report; each part's own
folder was written by :func:`~zmpkit.pipelines.demo.run_demo` as the part finished.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import NDArray

from zmpkit.analysis.report_document import Figure
from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.step_plot import Curve, plot_step_responses
from zmpkit.models import Dlipm
from zmpkit.pipelines.balance_document import step_trial_videos
from zmpkit.pipelines.demo import DemoResult, PartClock
from zmpkit.pipelines.demo_config import DemoConfig
from zmpkit.pipelines.demo_document import (
    LABELS,
    DemoParts,
    demo_document,
    format_optional,
    walk_side_by_side_videos,
)
from zmpkit.pipelines.walk import WalkResult
from zmpkit.pipelines.walk_figures import COMPARISON_FILE, write_effects_comparison
from zmpkit.signals.step_metrics import StepMetrics

__all__ = ["write_demo"]


def write_demo(
    result: DemoResult, out_dir: str | Path, echo: Callable[[str], None] = print
) -> DemoResult:
    """Write the model's figures and files, the walk comparison and the demo's report.

    ``out_dir`` is the folder :func:`~zmpkit.pipelines.demo.run_demo` wrote the parts into;
    it receives ``fig17_lipm_vs_dlipm.png``, ``fig18_dlipm_zeta08.png``,
    ``step_metrics.csv``, ``dlipm.yaml``, the walk comparison and the report. Their wall
    time is charged to the parts they belong to (models, walk figures).
    """
    config, out = result.config, Path(out_dir)
    times_s = dict(result.part_times_s)
    clock = PartClock(times_s)
    lipm_static = math.asin(config.zmp_step_m / config.length_m)
    figures = _figures(out, result.time_s, result.theta_rad, lipm_static, config)
    _write_metrics_csv(out / "step_metrics.csv", result.models, result.metrics)
    _write_params_yaml(out / "dlipm.yaml", result.models)
    clock.lap("models")
    comparison = _walk_comparison(result.walks, out)
    clock.lap("walk figures")
    balance = result.balance
    parts = DemoParts(
        result.models,
        result.metrics,
        figures,
        balance,
        result.walks,
        result.compensation,
        videos=walk_side_by_side_videos(result.walk_videos),
        balance_videos=step_trial_videos(balance[1], balance[0].videos) if balance else (),
        extra_figures=comparison,
        started_s=result.started_s,
        part_times_s=times_s,
    )
    report = write_report(demo_document(config, parts), out, config.report_format)
    echo("time by part: " + ", ".join(f"{k} {v:.0f} s" for k, v in times_s.items() if v))
    return replace(result, report_path=report, figures=figures, part_times_s=times_s)


def _walk_comparison(walks: dict[str, WalkResult], out: Path) -> tuple[Figure, ...]:
    """The rigid walk against the all-effects walk on shared axes (paper B Fig. 6)."""
    if not {"none", "all"} <= walks.keys():
        return ()
    path = write_effects_comparison(
        {k: (w.config, w.summary, w.record) for k, w in walks.items()}, out / COMPARISON_FILE
    )
    caption = (
        "The rigid walk (every effect off) and the walk with every effect on, same command: "
        "trunk pitch [rad] over the same four steps of their steady windows over time [s] "
        "(left), and its amplitude spectrum [rad] over each walk's steady window, the one of "
        "its summary (right), with the step frequency marked. Paper B Fig. 6 attributes the "
        "difference to the motor and its PID."
    )
    return (Figure(path, caption),)


def _figures(
    out: Path,
    t: NDArray[np.float64],
    theta: dict[str, NDArray[np.float64]],
    lipm_static: float,
    config: DemoConfig,
) -> tuple[Path, ...]:
    early = t <= 3.0
    fig17 = plot_step_responses(
        [Curve(LABELS[n], t[early], theta[n][early]) for n in ("lipm", "dlipm_si")],
        out / "fig17_lipm_vs_dlipm.png",
        title=f"Angular step response, ZMP step {config.zmp_step_m:g} m (paper A Fig. 17)",
        reference_rad=lipm_static,
        ylim_rad=(-0.01, 2.0 * lipm_static),
    )
    fig18 = plot_step_responses(
        [Curve(LABELS[n], t, theta[n]) for n in ("dlipm_si", "dlipm_paper_units")],
        out / "fig18_dlipm_zeta08.png",
        title=f"DLIPM designed for ζ = {config.zeta:g} (paper A Fig. 18)",
        reference_rad=lipm_static,
    )
    return fig17, fig18


def _write_metrics_csv(
    path: Path, models: dict[str, Dlipm], metrics: dict[str, StepMetrics]
) -> None:
    with path.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(
            [
                "model",
                "stable",
                "omega_n_rad_s",
                "zeta",
                "overshoot_pct",
                "rise_time_s",
                "settling_time_s_2pct",
                "final_value_rad",
            ]
        )
        for name, model in models.items():
            m = metrics.get(name)
            w.writerow(
                [
                    name,
                    model.is_stable,
                    format_optional(model.omega_n if model.is_stable else None),
                    format_optional(model.zeta if model.is_stable else None),
                    format_optional(None if m is None else m.overshoot_pct),
                    format_optional(None if m is None else m.rise_time_s),
                    format_optional(None if m is None else m.settling_time_s),
                    format_optional(None if m is None else m.final_value),
                ]
            )


def _write_params_yaml(path: Path, models: dict[str, Dlipm]) -> None:
    doc = {
        name: {
            "mass_kg": m.mass,
            "length_m": m.length,
            "k_a_N": m.k_a,
            "b_a_Ns": m.b_a,
            "gamma_rad_per_m_s2": m.gamma,
            "alpha_per_s": m.alpha,
            "beta_per_s2": m.beta,
        }
        for name, m in models.items()
    }
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
