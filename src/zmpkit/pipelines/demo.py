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
own ``run_x`` and ``write_x``); :func:`~zmpkit.pipelines.demo_files.write_demo` writes the
model's files, the walk comparison and the demo's report.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.models import Dlipm, paper_units_omega_n
from zmpkit.pipelines.balance import BalanceConfig, BalanceResult, run_balance
from zmpkit.pipelines.balance_files import BalanceArtifacts, write_balance
from zmpkit.pipelines.demo_config import DEMO_STEP_M, DemoConfig
from zmpkit.pipelines.progress import SILENT, Displays
from zmpkit.pipelines.walk import WalkResult, run_walk
from zmpkit.pipelines.walk_compensate import CompensateConfig, CompensateResult, run_walk_compensate
from zmpkit.pipelines.walk_compensate_files import write_walk_compensate
from zmpkit.pipelines.walk_files import SIDE_BY_SIDE_FILE, write_side_by_side, write_walk
from zmpkit.robots.registry import get_robot
from zmpkit.signals.step_metrics import StepMetrics, step_metrics

__all__ = ["DEMO_STEP_M", "DemoConfig", "DemoResult", "PartClock", "run_demo"]


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
        report_path: the report (None until
            :func:`~zmpkit.pipelines.demo_files.write_demo`).
        figures: the model figures, Fig. 17 and 18 (empty until
            :func:`~zmpkit.pipelines.demo_files.write_demo`).
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
    finishes; :func:`~zmpkit.pipelines.demo_files.write_demo` then writes the demo's own
    files and its report.
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
    clock = PartClock()
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


class PartClock:
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
    clock: PartClock,
) -> tuple[dict[str, WalkResult], tuple[Path, ...]]:
    """The walks by effect set, and their side-by-side video if asked for."""
    walks = {}
    title = config.walk_robot.title
    for effects in ("none", "all"):
        echo(f"virtual {title}: zmpkit walk --effects {effects} (10 s at 0.2 m/s)")
        with displays.simulation(f"walk, effects {effects}") as progress:
            walk = WalkConfig(robot=config.walk_robot, effects=effects)
            result = write_walk(
                run_walk(walk, progress), out / f"walk_{effects}", config.report_format
            )
        walks[effects] = result
    clock.lap("walks")
    if not config.video:
        return walks, ()
    echo(f"video: the rigid and the all-effects walk side by side ({SIDE_BY_SIDE_FILE})")
    video = write_side_by_side(list(walks.values()), out)
    clock.lap("walk video")
    return walks, () if video is None else (video,)


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


def _to_rad(name: str, angle: Any) -> Any:
    """``angle`` in [rad]: the paper-units design's [deg] converted, the others as they are."""
    return np.radians(angle) if name == "dlipm_paper_units" else angle
