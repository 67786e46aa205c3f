"""``zmpkit demo``: the main job on the built-in virtual robot.

1. The model: angular step responses of the LIPM and the DLIPM for a ZMP step (paper A
   §4.4, Fig. 17 and 18), with their step metrics: the report, the figures,
   ``step_metrics.csv`` and ``dlipm.yaml``.
2. The robot: ``zmpkit balance --quick`` on the balance robot (LIPM steps, identification,
   gain-scheduled DLIPM, Table 1) into ``balance/``, linked from the report.

3. Walking: the walking robot walks 10 s at 0.2 m/s with every effect off and on
   (``zmpkit walk``) into ``walk_none/`` and ``walk_all/``; the report compares their trunk
   oscillation (paper B Fig. 2, 6, 12).
4. Compensation: ``zmpkit walk compensate --method auto --quick`` into ``compensate/``
   (tuned ZMP offsets against the trunk oscillation, checked on walks not used for tuning).

With ``video`` (the default) it also draws the rigid and the all-effects walk side by side
(``walk_side_by_side.mp4``) and one balance step trial (``balance/step_trial.mp4``).
"""

from __future__ import annotations

import csv
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from zmpkit.analysis.report_document import Figure
from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.step_plot import Curve, plot_step_responses
from zmpkit.analysis.walk_video import SIDE_BY_SIDE_FILE, write_walks_side_by_side
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.models import Dlipm, paper_units_omega_n
from zmpkit.pipelines.balance import BalanceConfig, BalanceResult, run_balance
from zmpkit.pipelines.balance_document import step_trial_videos
from zmpkit.pipelines.balance_files import BalanceArtifacts, write_balance
from zmpkit.pipelines.demo_config import DEMO_STEP_M, DemoConfig
from zmpkit.pipelines.demo_document import (
    LABELS,
    DemoParts,
    demo_document,
    format_optional,
    walk_side_by_side_videos,
)
from zmpkit.pipelines.progress import SILENT, Displays
from zmpkit.pipelines.walk import WalkResult, run_walk
from zmpkit.pipelines.walk_compensate import CompensateConfig, CompensateResult, run_walk_compensate
from zmpkit.pipelines.walk_compensate_files import write_walk_compensate
from zmpkit.pipelines.walk_figures import COMPARISON_FILE, write_effects_comparison
from zmpkit.pipelines.walk_files import write_walk
from zmpkit.robots.registry import get_robot
from zmpkit.signals.step_metrics import StepMetrics, step_metrics

__all__ = ["DEMO_STEP_M", "DemoConfig", "DemoResult", "run_demo"]


@dataclass(frozen=True)
class DemoResult:
    """Paths of what the demo wrote, and the metrics it measured per model.

    ``videos`` are the MP4s (or the GIFs or keyframes written instead).
    """

    out_dir: Path
    report_path: Path
    figures: tuple[Path, ...]
    metrics: dict[str, StepMetrics]
    videos: tuple[Path, ...] = ()


def run_demo(
    out_dir: str | Path,
    config: DemoConfig | None = None,
    echo: Callable[[str], None] = print,
    displays: Displays = SILENT,
) -> DemoResult:
    """Run the demo and write its artefacts into ``out_dir`` (created if missing)."""
    started_s = time.time()
    config = config or DemoConfig()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    models = _demo_models(config)
    t = np.arange(0.0, config.duration_s + config.dt_s / 2, config.dt_s)
    theta = {name: _angle_rad(name, m, t, config.zmp_step_m) for name, m in models.items()}
    lipm_static = math.asin(config.zmp_step_m / config.length_m)
    metrics = {
        name: step_metrics(
            t,
            theta[name],
            reference=lipm_static,
            final_value=_to_rad(name, m.dc_gain * config.zmp_step_m),  # exact, linear model
        )
        for name, m in models.items()
        if m.is_stable
    }
    echo(f"DLIPM step responses for a {config.zmp_step_m:g} m ZMP step")
    clock = _PartClock()
    figures = _figures(out, t, theta, lipm_static, config)
    _write_metrics_csv(out / "step_metrics.csv", models, metrics)
    _write_params_yaml(out / "dlipm.yaml", models)
    clock.lap("models")
    balance = _run_balance(config, out, echo, displays) if config.balance else None
    clock.lap("balance")
    walks, walk_videos = (
        _run_walks(config, out, echo, displays, clock) if config.walking else ({}, ())
    )
    comparison = _walk_comparison(walks, out)
    clock.lap("walk figures")
    compensation = _run_compensation(config, out, echo, displays) if config.compensation else None
    clock.lap("compensation")
    balance_videos = balance[0].videos if balance is not None else ()
    parts = DemoParts(
        models,
        metrics,
        figures,
        balance,
        walks,
        compensation,
        videos=walk_side_by_side_videos(walk_videos),
        balance_videos=step_trial_videos(balance[1], balance_videos) if balance else (),
        extra_figures=comparison,
        started_s=started_s,
        part_times_s=clock.times_s,
    )
    report = write_report(demo_document(config, parts), out, config.report_format)
    echo("time by part: " + ", ".join(f"{k} {v:.0f} s" for k, v in clock.times_s.items() if v))
    return DemoResult(out, report, figures, metrics, walk_videos + balance_videos)


class _PartClock:
    """Wall time of each part of the demo [s], in the order they ran."""

    def __init__(self) -> None:
        self.times_s: dict[str, float] = {}
        self._last_s = time.perf_counter()

    def lap(self, part: str) -> None:
        """Charge the time since the last lap to ``part``."""
        now_s = time.perf_counter()
        self.times_s[part] = self.times_s.get(part, 0.0) + now_s - self._last_s
        self._last_s = now_s


def _run_compensation(
    config: DemoConfig, out: Path, echo: Callable[[str], None], displays: Displays
) -> CompensateResult:

    title = get_robot(config.walk_robot).title
    echo(f"virtual {title}: zmpkit walk compensate --method auto --quick")
    with displays.stages() as progress:
        result = run_walk_compensate(
            CompensateConfig(robot=config.walk_robot, method="auto", quick=True),
            out / "compensate",
            progress,
        )
    return write_walk_compensate(result, out / "compensate", config.report_format)


def _run_walks(
    config: DemoConfig,
    out: Path,
    echo: Callable[[str], None],
    displays: Displays,
    clock: _PartClock,
) -> tuple[dict[str, WalkResult], tuple[Path, ...]]:
    """The walks by effect set, and their side-by-side video if asked for."""
    walks, records = {}, []
    title = config.walk_robot.title
    for effects in ("none", "all"):
        echo(f"virtual {title}: zmpkit walk --effects {effects} (10 s at 0.2 m/s)")
        with displays.simulation(f"walk, effects {effects}") as progress:
            walk = WalkConfig(robot=config.walk_robot, effects=effects)
            result = write_walk(
                run_walk(walk, progress), out / f"walk_{effects}", config.report_format
            )
        walks[effects] = result
        records.append((result.config, result.record))
    clock.lap("walks")
    if not config.video:
        return walks, ()
    echo(f"video: the rigid and the all-effects walk side by side ({SIDE_BY_SIDE_FILE})")
    video = write_walks_side_by_side(records, out / SIDE_BY_SIDE_FILE)
    clock.lap("walk video")
    return walks, () if video.path is None else (video.path,)


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


def _run_balance(
    config: DemoConfig, out: Path, echo: Callable[[str], None], displays: Displays
) -> tuple[BalanceArtifacts, BalanceResult]:

    title = config.balance_robot.title
    echo(f"virtual {title}: zmpkit balance --quick (LIPM steps, DLIPM identification, Table 1)")
    with displays.sweeps() as progress:
        balance = BalanceConfig.quick(robot=config.balance_robot, video=config.video)
        result = run_balance(balance, out / "balance", progress=progress, echo=echo)
    artifacts = write_balance(result, out / "balance", config.report_format)
    return artifacts, result


def _demo_models(config: DemoConfig) -> dict[str, Dlipm]:
    m, length = config.mass_kg, config.length_m
    lipm = Dlipm.lipm(m, length)
    si_design = Dlipm.design(m, length, dc_gain=1.0 / length, zeta=config.zeta)
    paper_beta = paper_units_omega_n(length) ** 2
    paper_design = Dlipm.design(m, length, dc_gain=lipm.gamma / paper_beta, zeta=config.zeta)
    return {"lipm": lipm, "dlipm_si": si_design, "dlipm_paper_units": paper_design}


def _angle_rad(name: str, model: Dlipm, t: np.ndarray, step_m: float) -> np.ndarray:
    """Ankle angle [rad]; the paper-units design outputs degrees (paper A's code does)."""
    return _to_rad(name, model.step_response(t, step_m).theta)


def _to_rad(name: str, angle):
    return np.radians(angle) if name == "dlipm_paper_units" else angle


def _figures(out: Path, t, theta, lipm_static: float, config: DemoConfig) -> tuple[Path, ...]:
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


def _write_metrics_csv(path: Path, models: dict[str, Dlipm], metrics) -> None:
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
                    format_optional(m and m.overshoot_pct),
                    format_optional(m and m.rise_time_s),
                    format_optional(m and m.settling_time_s),
                    format_optional(m and m.final_value),
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
