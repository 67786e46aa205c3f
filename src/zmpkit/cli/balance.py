"""``zmpkit balance``: paper A end to end on a virtual robot."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from zmpkit.cli.options import SEED, WORKERS, report_option
from zmpkit.cli.progress import SweepProgress
from zmpkit.cli.robot_option import robot_option
from zmpkit.cli.video_option import video_option
from zmpkit.control import PAPER_A_TIME_SCALE
from zmpkit.experiments.config import parse_targets
from zmpkit.experiments.ft_faults import FAULT_KINDS
from zmpkit.pipelines.balance import (
    FAST_TIME_SCALE,
    FAST_ZETA,
    MIN_CHOSEN_TARGETS,
    BalanceConfig,
    fit_targets_of,
    run_balance,
)
from zmpkit.pipelines.balance_files import write_balance
from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT
from zmpkit.robots.robot import Robot

__all__ = ["EXIT_BARS_NOT_MET", "balance_command"]

EXIT_BARS_NOT_MET = 1
"""Exit code of ``balance --strict`` when a bar is missed or undefined."""


@click.command("balance")
@robot_option(DEFAULT_BALANCE_ROBOT, needs="balance", as_robot=True)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    required=True,
    help="Output folder (resumed: finished trials are kept).",
)
@click.option(
    "--quick", is_flag=True, help="Fewer targets and shorter holds (a few minutes on 2 cores)."
)
@click.option(
    "--truth",
    type=click.Path(path_type=Path),
    help="Truth YAML replacing the virtual robot's shipped one.",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--effects",
    default="all",
    show_default=True,
    help="Simulated effects: all, none, or letters M,I,G,F,S.",
)
@click.option(
    "--plane",
    "planes",
    multiple=True,
    type=click.Choice(("sagittal", "frontal")),
    help="Plane(s) to run; default both.",
)
@click.option(
    "--targets",
    help="ZMP targets [m], both planes: START:STOP:STEP (stop included) or a comma list, at "
    f"least {MIN_CHOSEN_TARGETS}; every other one and the largest are fitted on, the others "
    "validate. Default: shares of 0.3 x the support polygon's nearest edge.",
)
@click.option("--workers", type=WORKERS, default=2, show_default=True, help="Parallel processes.")
@click.option(
    "--dlipm-pace",
    type=click.Choice(("servo", "fast", "paper")),
    default="servo",
    show_default=True,
    help="servo: the fastest DLIPM the servos' acceleration limit allows, per target; "
    "fast: time scale 2 and zeta 1, shaped by the servos' limiter as the LIPM's step is "
    "(settles sooner than the LIPM at most targets, examples/balance_pacing.py); "
    "paper: paper A's fixed time scale sqrt(180/pi).",
)
@click.option(
    "--max-hold",
    type=float,
    default=None,
    help="Longest hold [s]: a hold is extended until the ZMP settles (creep included); "
    "default 60 (quick: 45). 0: fixed holds.",
)
@click.option(
    "--strict",
    is_flag=True,
    help=f"Exit with code {EXIT_BARS_NOT_MET} when a bar of paper A is missed or undefined "
    "(default: the verdict is printed and the exit code is 0).",
)
@click.option(
    "--dlipm-feedback",
    is_flag=True,
    help="Also run LIPM+PID and DLIPM+feedback (a clamped PI on the measured ZMP), two more "
    "column groups of Table 1.",
)
@click.option(
    "--fault",
    "faults",
    multiple=True,
    type=click.Choice(FAULT_KINDS),
    help="Inject F-T faults (bursts of 0.1 s every 1 s from 1 s after the step) into what the "
    "feedback controllers read; repeat for several kinds (taken in turn). Needs "
    "--dlipm-feedback.",
)
@report_option
@video_option(False, "one step trial (the DLIPM at the largest target, step_trial.mp4)")
def balance_command(
    robot: Robot,
    out_dir: Path,
    quick: bool,
    truth: Path | None,
    seed: int,
    effects: str,
    planes: tuple[str, ...],
    targets: str | None,
    workers: int,
    dlipm_pace: str,
    max_hold: float | None,
    strict: bool,
    dlipm_feedback: bool,
    faults: tuple[str, ...],
    report_format: str,
    video: bool,
) -> int:
    """Paper A end to end: LIPM steps, DLIPM identification, scheduled controller, Table 1."""
    changes: dict[str, Any] = {
        "robot": robot,
        "seed": seed,
        "effects": effects,
        "workers": workers,
        "truth": None if truth is None else str(truth),
        "video": video,
        "dlipm_feedback": dlipm_feedback,
        "faults": faults,
    }
    if planes:
        changes["planes"] = planes
    if targets is not None:
        chosen = parse_targets(targets, "--targets")
        changes.update(targets_m=chosen, fit_targets_m=fit_targets_of(chosen))
    if dlipm_pace == "paper":
        changes.update(time_scale=PAPER_A_TIME_SCALE, servo_paced=False)
    elif dlipm_pace == "fast":
        changes.update(time_scale=FAST_TIME_SCALE, servo_paced=False, zeta=FAST_ZETA)
    if max_hold is not None:
        changes["max_hold_s"] = max_hold if max_hold > 0.0 else None
    config = BalanceConfig.quick(**changes) if quick else BalanceConfig(**changes)
    with SweepProgress() as progress:
        result = run_balance(config, out_dir, progress=progress, echo=click.echo)
    artifacts = write_balance(result, out_dir, report_format)
    click.echo(f"report: {artifacts.report}")
    for path in artifacts.videos:
        click.echo(f"video: {path}")
    click.echo("verdict (paper A's bars):")
    for verdict in artifacts.verdicts.values():
        for line in verdict.lines():
            click.echo(f"  {line}")
    for plane, why in artifacts.failed_planes.items():
        click.echo(f"  {plane}: not finished, bars undefined ({why})")
    return _exit_code(artifacts.met, strict)


def _exit_code(met: bool, strict: bool) -> int:
    """0, or :data:`EXIT_BARS_NOT_MET` under ``--strict`` when a bar is not met; says which."""
    if met:
        click.echo("every bar met: exit 0")
        return 0
    if strict:
        click.echo(f"--strict: a bar is missed or undefined: exit {EXIT_BARS_NOT_MET}")
        return EXIT_BARS_NOT_MET
    click.echo(f"a bar is missed or undefined; exit 0 (--strict exits {EXIT_BARS_NOT_MET})")
    return 0
