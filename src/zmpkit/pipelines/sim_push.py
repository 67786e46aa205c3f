"""The ``zmpkit sim push`` pipeline: a step / push sweep on a virtual robot, analysed.

:func:`run_sim_push` writes into the output folder, trial by trial, the dataset (one CSV per
trial + ``meta.json``, see :mod:`zmpkit.experiments.dataset`; a rerun resumes it);
:func:`~zmpkit.pipelines.sim_push_files.write_sim_push` writes ``steady_state.csv``, ``steps.png``
and the report.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

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
)
from zmpkit.experiments.sweep import ProgressCallback, check_sweep
from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT, get_robot, robots_that
from zmpkit.robots.robot import Robot
from zmpkit.signals import PLANES
from zmpkit.sim.effect_set import EFFECT_LETTERS, EffectSet

__all__ = ["SimPushResult", "run_sim_push", "sim_push_config"]


@dataclass(frozen=True)
class SimPushResult:
    """What ``zmpkit sim push`` produced.

    Attributes:
        config: the sweep.
        dataset: the dataset as read back from the output folder.
        responses: measured / expected ZMP and steady-state figures per trial.
        files: the files written by role (``steady_state``, ``figure``, ``report``; empty
            until :func:`~zmpkit.pipelines.sim_push_files.write_sim_push`).
        started_s: when the run started [s since the epoch].
    """

    config: StepExperimentConfig
    dataset: StepDataset
    responses: tuple[TrialResponse, ...]
    files: dict[str, Path] = field(default_factory=dict)
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


def run_sim_push(
    config: StepExperimentConfig,
    out_dir: str | Path,
    *,
    workers: int = DEFAULT_WORKERS,
    progress: ProgressCallback | None = None,
) -> SimPushResult:
    """Run (or resume) the sweep of ``config`` into ``out_dir`` and analyse each trial."""
    started_s = time.time()
    dataset = run_step_sweep(config, Path(out_dir), workers=workers, progress=progress)
    return SimPushResult(config, dataset, step_responses(dataset), started_s=started_s)
