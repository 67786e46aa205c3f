"""``zmpkit sim``: experiments on a virtual robot (the step/push sweep)."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.options import SEED, WORKERS, Bounded, report_option
from zmpkit.cli.progress import TrialProgressBar
from zmpkit.cli.robot_option import robot_option
from zmpkit.experiments import MAX_HOLD_S, MAX_PUSH_DURATION_S, MAX_PUSH_FORCE_N
from zmpkit.pipelines.sim_push import run_sim_push, sim_push_config
from zmpkit.pipelines.sim_push_files import write_sim_push
from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT
from zmpkit.robots.robot import Robot

__all__ = ["sim_group", "sim_push_command"]


@click.group("sim")
def sim_group() -> None:
    """Run experiments on a virtual robot and write their datasets and analyses."""


@sim_group.command("push")
@robot_option(DEFAULT_BALANCE_ROBOT, needs="balance", as_robot=True)
@click.option(
    "--targets",
    default="0:0.10:0.01",
    show_default=True,
    help="ZMP targets [m]: START:STOP:STEP (stop included) or a comma list, e.g. 0,0.05.",
)
@click.option(
    "--plane", default="sagittal", show_default=True, help="sagittal (ZMP x) or frontal (ZMP y)."
)
@click.option(
    "--effects",
    default="all",
    show_default=True,
    help="Simulated effects: all, none, or letters M,I,G,F,S (motor, inductance, gear, flex, "
    "sensors).",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    required=True,
    help="Output folder (resumed if it holds the same sweep).",
)
@click.option(
    "--truth", type=click.Path(path_type=Path), help="Truth YAML replacing the shipped one."
)
@click.option(
    "--push-force",
    type=Bounded(-MAX_PUSH_FORCE_N, MAX_PUSH_FORCE_N, "N"),
    help="Push at the CoM along the plane's axis [N].",
)
@click.option(
    "--push-duration",
    type=Bounded(0.0, MAX_PUSH_DURATION_S, "s", low_open=True),
    help="Duration of the push [s].",
)
@click.option(
    "--hold",
    type=Bounded(0.0, MAX_HOLD_S, "s", low_open=True),
    help="Recorded time after the step [s] (default 15).",
)
@click.option("--workers", type=WORKERS, default=2, show_default=True, help="Parallel processes.")
@report_option
def sim_push_command(
    robot: Robot,
    targets: str,
    plane: str,
    effects: str,
    seed: int,
    out_dir: Path,
    truth: Path | None,
    push_force: float | None,
    push_duration: float | None,
    hold: float | None,
    workers: int,
    report_format: str,
) -> None:
    """ZMP step / push sweep (paper A Fig. 14): dataset, steady_state.csv and steps.png."""
    config = sim_push_config(
        robot=robot,
        targets=targets,
        plane=plane,
        effects=effects,
        seed=seed,
        truth=truth,
        push_force=push_force,
        push_duration=push_duration,
        hold=hold,
    )

    with TrialProgressBar(len(config.targets_m)) as progress:
        result = run_sim_push(config, out_dir, workers=workers, progress=progress)
    result = write_sim_push(result, out_dir, report_format)
    for line in result.warnings:
        click.echo(f"warning: {line}", err=True)
    click.echo(
        f"{len(result.dataset.trials)} trials in {out_dir}; wrote "
        f"{result.files['steady_state']} and {result.files['figure']}"
    )
    click.echo(f"report: {result.files['report']}")
