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

:func:`run_demo` runs the parts, each written into its folder as it finishes (each part's
own ``run_x`` and ``write_x``); :func:`write_demo` writes the model's files, the walk
comparison and the demo's report.
"""

from __future__ import annotations

import csv
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import NDArray

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

__all__ = ["DEMO_STEP_M", "DemoConfig", "DemoResult", "run_demo", "write_demo"]


@dataclass(frozen=True, eq=False)
class DemoResult:
    """What the demo ran: the models' step responses and each part's result.

    Attributes:
        config: what was asked.
        out_dir: the folder the parts were written into as each finished.
        time_s: the step responses' sample times [s], shape (N,).
        theta_rad: each model's ankle angle after the ZMP step [rad], shape (N,).
        models: the pendulum models by key of :data:`~zmpkit.pipelines.demo_sections.LABELS`.
        metrics: step-response metrics of each stable model.
        balance: the balance part's written artefacts and result, or None.
        walks: the walks by effect set (``none``, ``all``), each written; empty without walking.
        walk_videos: the walks side by side (MP4, or the GIF or keyframes written instead).
        compensation: the compensation part, written, or None.
        started_s: when the demo started [s since the epoch].
        part_times_s: wall time of each part, in the order they ran [s].
        report_path: the report (None until :func:`write_demo`).
        figures: the model figures, Fig. 17 and 18 (empty until :func:`write_demo`).
    """

    config: DemoConfig
    out_dir: Path
    time_s: NDArray[np.float64]
    theta_rad: dict[str, NDArray[np.float64]]
    models: dict[str, Dlipm]
    metrics: dict[str, StepMetrics]
    balance: tuple[BalanceArtifacts, BalanceResult] | None
    walks: dict[str, WalkResult]
    walk_videos: tuple[Path, ...]
    compensation: CompensateResult | None
    started_s: float
    part_times_s: dict[str, float]
    report_path: Path | None = None
    figures: tuple[Path, ...] = ()

    @property
    def videos(self) -> tuple[Path, ...]:
        """Every video written: the walks side by side, then the balance step trial."""
        return self.walk_videos + (self.balance[0].videos if self.balance is not None else ())


def run_demo(
    config: DemoConfig | None = None,
    out_dir: str | Path = "out/demo",
    echo: Callable[[str], None] = print,
    displays: Displays = SILENT,
) -> DemoResult:
    """Run every part of the demo; each part's folder is written into ``out_dir`` as it ends.

    The balance, walk and compensation parts take minutes: each writes its own folder
    (``balance/``, ``walk_none/``, ``walk_all/``, ``compensate/``, the walk video) when it
    finishes; :func:`write_demo` then writes the demo's own files and its report.
    """
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
    clock.lap("models")  # its figures and files are drawn and written by write_demo
    balance = _run_balance(config, out, echo, displays) if config.balance else None
    clock.lap("balance")
    walks, walk_videos = (
        _run_walks(config, out, echo, displays, clock) if config.walking else ({}, ())
    )
    clock.lap("walk figures")  # the comparison is drawn by write_demo
    compensation = _run_compensation(config, out, echo, displays) if config.compensation else None
    clock.lap("compensation")
    return DemoResult(
        config, out, t, theta, models, metrics, balance, walks, walk_videos, compensation,
        started_s, clock.times_s,
    )  # fmt: skip


def write_demo(
    result: DemoResult, out_dir: str | Path, echo: Callable[[str], None] = print
) -> DemoResult:
    """Write the model's figures and files, the walk comparison and the demo's report.

    ``out_dir`` is the folder :func:`run_demo` wrote the parts into; it receives
    ``fig17_lipm_vs_dlipm.png``, ``fig18_dlipm_zeta08.png``, ``step_metrics.csv``,
    ``dlipm.yaml``, the walk comparison and the report. Their wall time is charged to the
    parts they belong to (models, walk figures).
    """
    config, out = result.config, Path(out_dir)
    times_s = dict(result.part_times_s)
    clock = _PartClock(times_s)
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


class _PartClock:
    """Wall time of each part of the demo [s], in the order they ran."""

    def __init__(self, times_s: dict[str, float] | None = None) -> None:
        self.times_s: dict[str, float] = {} if times_s is None else times_s
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
