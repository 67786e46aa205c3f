"""The ``zmpkit sim push`` pipeline: a step / push sweep on a virtual robot, analysed.

Writes into the output folder the dataset (one CSV per trial + ``meta.json``, see
:mod:`zmpkit.experiments.dataset`), ``steady_state.csv`` (columns
:data:`~zmpkit.experiments.response.STEADY_STATE_COLUMNS`) and ``steps.png`` (measured vs
expected ZMP of every target, like paper A Fig. 14).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from zmpkit.analysis.zmp_steps_plot import ZmpStepCurve, plot_zmp_steps
from zmpkit.errors import ParameterError
from zmpkit.experiments import (
    DEFAULT_WORKERS,
    MAX_HOLD_S,
    MAX_PUSH_DURATION_S,
    MAX_PUSH_FORCE_N,
    PushConfig,
    StepDataset,
    StepExperimentConfig,
    TrialResponse,
    parse_targets,
    run_step_sweep,
    step_responses,
    write_steady_state_csv,
)
from zmpkit.experiments.sweep import ProgressCallback, check_sweep
from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT, get_robot, robots_that
from zmpkit.robots.robot import Robot
from zmpkit.signals import PLANES
from zmpkit.sim.effect_set import EFFECT_LETTERS, EffectSet

__all__ = [
    "STEADY_STATE_FILE",
    "STEPS_FIGURE_FILE",
    "SimPushResult",
    "run_sim_push",
    "sim_push_config",
]

STEADY_STATE_FILE = "steady_state.csv"
STEPS_FIGURE_FILE = "steps.png"
_AXIS_LABEL = {"sagittal": "ZMP x (forward)", "frontal": "ZMP y (left)"}


@dataclass(frozen=True)
class SimPushResult:
    """What ``zmpkit sim push`` produced.

    Attributes:
        dataset: the dataset as read back from the output folder.
        responses: measured / expected ZMP and steady-state figures per trial.
        steady_state_path: ``steady_state.csv``.
        figure_path: ``steps.png``.
        started_s: when the run started [s since the epoch].
    """

    dataset: StepDataset
    responses: tuple[TrialResponse, ...]
    steady_state_path: Path
    figure_path: Path
    started_s: float = field(default_factory=time.time)

    @property
    def warnings(self) -> tuple[str, ...]:
        """One line per trial that did not settle over its steady window."""
        out = []
        for r in self.responses:
            if r.settled:
                continue
            what = (
                "undefined" if r.tail_spread_m is None else f"spans {1e3 * r.tail_spread_m:.1f} mm"
            )
            span = r.steady_window_s[1] - r.steady_window_s[0]
            out.append(
                f"target {r.zmp_ref:g} m not settled: its ZMP {what} over the last {span:g} s; "
                "try a longer --hold"
            )
        return tuple(out)


def _choice(option: str, value: str, valid: tuple[str, ...]) -> str:
    if value not in valid:
        raise ParameterError(f"{option} expects one of {', '.join(valid)}; got {value!r}")
    return value


def _robot(text: Robot | str) -> Robot:
    try:
        return get_robot(text, needs="balance")
    except ParameterError as exc:
        raise ParameterError(
            f"--robot expects one of {', '.join(robots_that('balance'))} or a robot.yaml file "
            f"with a balance model; {exc}"
        ) from None


def _effects(text: str) -> str:
    try:
        return EffectSet.parse(text).letters
    except ParameterError:
        letters = ",".join(EFFECT_LETTERS)
        raise ParameterError(
            f"--effects expects all, none or comma-separated letters from {letters} "
            f"(e.g. M,G,S); got {text!r}"
        ) from None


def _push(force: float | None, duration: float | None) -> PushConfig | None:
    if force is None and duration is None:
        return None
    if force is None or duration is None:
        raise ParameterError(
            "--push-force N and --push-duration S go together; "
            f"got --push-force {force} --push-duration {duration}"
        )
    if not abs(force) <= MAX_PUSH_FORCE_N:
        raise ParameterError(
            f"--push-force expects a force in [-{MAX_PUSH_FORCE_N:g}, {MAX_PUSH_FORCE_N:g}] N; "
            f"got {force}"
        )
    if not 0 < duration <= MAX_PUSH_DURATION_S:
        raise ParameterError(
            f"--push-duration expects a duration in (0, {MAX_PUSH_DURATION_S:g}] s; got {duration}"
        )
    return PushConfig(force, duration)


def sim_push_config(
    *,
    robot: Robot | str = DEFAULT_BALANCE_ROBOT,
    targets: str = "0:0.10:0.01",
    plane: str = "sagittal",
    effects: str = "all",
    seed: int = 0,
    truth: str | Path | None = None,
    push_force: float | None = None,
    push_duration: float | None = None,
    hold: float | None = None,
) -> StepExperimentConfig:
    """The sweep configuration from the command's option values (text as typed).

    Raises:
        ParameterError: naming the option and the form it expects.
    """
    extra: dict[str, Any] = {} if hold is None else {"hold_s": hold}
    if hold is not None and not 0 < hold <= MAX_HOLD_S:
        raise ParameterError(f"--hold expects a duration in (0, {MAX_HOLD_S:g}] s; got {hold}")
    if seed < 0:
        raise ParameterError(f"--seed expects an integer >= 0; got {seed}")
    config = StepExperimentConfig(
        robot=_robot(robot),
        targets_m=parse_targets(targets, "--targets"),
        plane=_choice("--plane", plane, PLANES),
        effects=_effects(effects),
        seed=seed,
        push=_push(push_force, push_duration),
        truth=None if truth is None else str(truth),
        **extra,
    )
    check_sweep(config)
    return config


def _title(config: StepExperimentConfig) -> str:
    push = ""
    if config.push is not None:
        push = f", push {config.push.force_n:g} N for {config.push.duration_s:g} s"
    return (
        f"{config.robot.title} {config.plane} ZMP steps, effects {config.effects}, "
        f"seed {config.seed}{push}"
    )


def run_sim_push(
    config: StepExperimentConfig,
    out_dir: str | Path,
    *,
    workers: int = DEFAULT_WORKERS,
    progress: ProgressCallback | None = None,
) -> SimPushResult:
    """Run (or resume) the sweep of ``config`` into ``out_dir`` and write its analysis."""
    started_s = time.time()
    out = Path(out_dir)
    dataset = run_step_sweep(config, out, workers=workers, progress=progress)
    responses = step_responses(dataset)
    csv_path = write_steady_state_csv(responses, out / STEADY_STATE_FILE)
    curves = [
        ZmpStepCurve(f"{1000 * r.zmp_ref:g} mm", r.time_since_step, r.zmp_measured, r.zmp_expected)
        for r in responses
    ]
    figure = plot_zmp_steps(
        curves, out / STEPS_FIGURE_FILE, title=_title(config), axis_label=_AXIS_LABEL[config.plane]
    )
    return SimPushResult(dataset, responses, csv_path, figure, started_s)
