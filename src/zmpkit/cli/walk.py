"""``zmpkit walk`` and ``zmpkit walk compensate``: paper B on a walking robot."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.cli.app import cli, format_or_undefined, robot_option
from zmpkit.cli.progress import SimTimeProgress, StageProgress
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.pipelines.walk import run_walk, write_walk
from zmpkit.pipelines.walk_compensate import CompensateConfig, run_walk_compensate
from zmpkit.pipelines.walk_compensate_report import write_walk_compensate
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT

__all__ = ["walk_compensate_command", "walk_group"]


@cli.group("walk", invoke_without_command=True)
@robot_option(DEFAULT_WALK_ROBOT, needs="walking")
@click.option("--speed", type=float, default=0.2, show_default=True, help="Forward speed [m/s].")
@click.option(
    "--step-duration", type=float, default=0.5, show_default=True, help="Duration of one step [s]."
)
@click.option("--duration", type=float, default=10.0, show_default=True, help="Walking time [s].")
@click.option(
    "--effects",
    default="all",
    show_default=True,
    help="Simulated effects: all, none, or letters M,I,G,F,S.",
)
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--truth",
    type=click.Path(path_type=Path),
    help="Truth YAML replacing the virtual robot's shipped one.",
)
@click.option(
    "--out",
    "out_dir",
    type=click.Path(path_type=Path),
    help="Output folder (required when walking).",
)
@click.pass_context
def walk_group(
    ctx: click.Context,
    robot: str,
    speed: float,
    step_duration: float,
    duration: float,
    effects: str,
    seed: int,
    truth: Path | None,
    out_dir: Path | None,
) -> None:
    """Walk the virtual robot with the 3D-LIPM pattern (paper B) and analyse the walk."""
    if ctx.invoked_subcommand is not None:
        return
    if out_dir is None:
        raise click.UsageError("walking needs --out DIR")

    config = WalkConfig(
        robot=robot,
        speed_mps=speed,
        step_duration_s=step_duration,
        duration_s=duration,
        effects=effects,
        seed=seed,
        truth=None if truth is None else str(truth),
    )
    with SimTimeProgress(f"walk ({config.effects or 'none'})") as progress:
        result = run_walk(config, progress=progress)
    write_walk(result, out_dir)
    s = result.summary
    speed_text = format_or_undefined(s.mean_speed_mps, ".4f")
    peak_hz = format_or_undefined(s.trunk_pitch_peak_hz, ".2f")
    peak_rad = format_or_undefined(s.trunk_pitch_peak_amplitude_rad, ".4f")
    click.echo(
        f"fell: {s.fell}; speed {speed_text} m/s (commanded {s.commanded_speed_mps:.4f}); "
        f"trunk pitch peak {peak_hz} Hz, {peak_rad} rad"
    )
    click.echo(f"summary: {Path(out_dir) / 'summary.json'}")


@walk_group.command("compensate")
@click.option(
    "--method",
    type=click.Choice(("alg1", "alg2", "half-sine", "sawtooth", "fourier", "auto")),
    default="auto",
    show_default=True,
    help="alg1/alg2: paper B's Algorithms 1 and 2; half-sine, sawtooth, fourier: a tuned "
    "periodic offset on the desired ZMP; auto: tune every shape and keep the best.",
)
@robot_option(DEFAULT_WALK_ROBOT, needs="walking")
@click.option("--quick", is_flag=True, help="Fewer tuning walks (under 5 min on 2 cores).")
@click.option("--speed", type=float, default=0.2, show_default=True, help="Tuning speed [m/s].")
@click.option("--effects", default="all", show_default=True, help="Simulated effects.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option("--workers", type=int, default=2, show_default=True, help="Parallel processes.")
@click.option(
    "--out", "out_dir", type=click.Path(path_type=Path), required=True, help="Output folder."
)
def walk_compensate_command(
    method: str,
    robot: str,
    quick: bool,
    speed: float,
    effects: str,
    seed: int,
    workers: int,
    out_dir: Path,
) -> None:
    """Compensate the walk's model abstractions; validate on walks not used for tuning."""
    config = CompensateConfig(
        method=method,
        robot=robot,
        quick=quick,
        speed_mps=speed,
        effects=effects,
        seed=seed,
        workers=workers,
    )
    with StageProgress() as progress:
        result = run_walk_compensate(config, out_dir, progress=progress)
    write_walk_compensate(result, out_dir)
    s = result.summary
    if s.peak_reduction_pct is None or s.std_reduction_pct is None:
        click.echo(f"{s.method}: no validation walk where both versions stood to compare")
    else:
        click.echo(
            f"{s.method}: step-frequency peak {s.peak_reduction_pct:.1f} % lower, "
            f"oscillation std {s.std_reduction_pct:.1f} % lower on "
            f"{s.walks_compared} validation walks; compensated falls: "
            f"{s.compensated_falls}"
        )
    click.echo(f"summary: {Path(out_dir) / 'summary.json'}")
