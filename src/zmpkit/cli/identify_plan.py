"""``zmpkit identify plan``: which experiments pin which parameters, before recording."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.options import SEED, WORKERS, Bounded
from zmpkit.cli.progress import StageProgress
from zmpkit.cli.robot_option import robot_option
from zmpkit.pipelines.identify_plan import IdentifyPlanConfig, run_identify_plan
from zmpkit.pipelines.identify_plan_files import percent, write_identify_plan
from zmpkit.robots.registry import DEFAULT_FIT_ROBOT
from zmpkit.robots.robot import Robot

__all__ = ["identify_plan_command"]


@click.command("plan")
@robot_option(DEFAULT_FIT_ROBOT, needs="fit", as_robot=True)
@click.option(
    "--effects",
    default="M,G",
    show_default=True,
    help="Effects whose parameters the fit would fit: letters M, I, G, F, S, C.",
)
@click.option("--quick", is_flag=True, help="Plan for the quick fit's parameters.")
@click.option(
    "--duration",
    type=Bounded(1.0, 60.0, "s"),
    default=6.0,
    show_default=True,
    help="Each candidate walk's length [s].",
)
@click.option("--workers", type=WORKERS, default=2, show_default=True, help="Local threads.")
@click.option("--seed", type=SEED, default=1, show_default=True, help="Seed of the recordings.")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
def identify_plan_command(
    robot: Robot, effects: str, quick: bool, duration: float, workers: int, seed: int,
    out_dir: Path,
) -> None:  # fmt: skip
    """Say which experiments pin which parameters, and which set to record.

    Records every candidate experiment once from the robot's nominal model, measures what
    each pins from the fit's cost curvature (every other parameter free), and chooses the
    set to record; writes plan.csv, selection.csv, the chosen experiments' protocols
    (targets.csv + manifest.yaml) and plan.md.
    """
    config = IdentifyPlanConfig(robot, effects, quick, duration, workers, seed)
    with StageProgress() as progress:
        result = run_identify_plan(config, out_dir, progress)
    files = write_identify_plan(result, out_dir)
    names = [p.name for p in result.parameters]
    for judged in result.alone:
        pairs = zip(names, judged.marginal, strict=True)
        cells = ", ".join(f"{n} {percent(m)} %" for n, m in pairs)
        click.echo(f"{judged.experiments[0]}: pins {sum(judged.pinned)} ({cells})")
    if result.chosen:
        best = result.chosen[-1]
        click.echo(
            f"record: {', '.join(best.experiments)} -> pins {sum(best.pinned)} of {len(names)}"
        )
    for line in result.dropped:
        click.echo(f"not recorded: {line}")
    click.echo(f"plan: {files['plan']}  report: {files['report']}")
