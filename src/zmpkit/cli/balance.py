"""``zmpkit balance``: paper A end to end on a virtual robot."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from zmpkit.cli.app import cli, robot_option
from zmpkit.cli.options import SEED, WORKERS
from zmpkit.cli.progress import SweepProgress
from zmpkit.control import PAPER_A_TIME_SCALE
from zmpkit.pipelines.balance import BalanceConfig, run_balance
from zmpkit.pipelines.balance_report import write_balance_outputs
from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT

__all__ = ["balance_command"]


@cli.command("balance")
@robot_option(DEFAULT_BALANCE_ROBOT, needs="balance")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    required=True,
    help="Output folder (resumed: finished trials are kept).",
)
@click.option("--quick", is_flag=True, help="Fewer targets and shorter holds (under 2 min).")
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
@click.option("--workers", type=WORKERS, default=2, show_default=True, help="Parallel processes.")
@click.option(
    "--dlipm-pace",
    type=click.Choice(("servo", "paper")),
    default="servo",
    show_default=True,
    help="servo: the fastest DLIPM the servos' acceleration limit allows, per target; "
    "paper: paper A's fixed time scale sqrt(180/pi).",
)
def balance_command(
    robot: str,
    out_dir: Path,
    quick: bool,
    truth: Path | None,
    seed: int,
    effects: str,
    planes: tuple[str, ...],
    workers: int,
    dlipm_pace: str,
) -> None:
    """Paper A end to end: LIPM steps, DLIPM identification, scheduled controller, Table 1."""
    changes: dict[str, Any] = {
        "robot": robot,
        "seed": seed,
        "effects": effects,
        "workers": workers,
        "truth": None if truth is None else str(truth),
    }
    if planes:
        changes["planes"] = planes
    if dlipm_pace == "paper":
        changes.update(time_scale=PAPER_A_TIME_SCALE, servo_paced=False)
    config = BalanceConfig.quick(**changes) if quick else BalanceConfig(**changes)
    with SweepProgress() as progress:
        result = run_balance(config, out_dir, progress=progress, echo=click.echo)
    artifacts = write_balance_outputs(result, out_dir)
    click.echo(f"report: {artifacts.report}")
