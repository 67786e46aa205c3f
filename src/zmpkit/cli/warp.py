"""``zmpkit warp``: MuJoCo Warp's persistent kernel cache (where it is, how to fill it)."""

from __future__ import annotations

import click

from zmpkit.robots.registry import get_robot, missing_reason, robots_that
from zmpkit.sim.warp_cache import CACHE_ENV, warp_cache_base

__all__ = ["warp_cache_command", "warp_group", "warp_warm_up_command"]


@click.group("warp")
def warp_group() -> None:
    """MuJoCo Warp (the fit's --backend warp): its kernel cache and warm-up."""


@warp_group.command("cache")
def warp_cache_command() -> None:
    """Print where zmpkit keeps MuJoCo Warp's compiled kernels (needs no Warp)."""
    click.echo(f"{warp_cache_base()}/<warp version> (set {CACHE_ENV} to move it)")


@warp_group.command("warm-up")
@click.option(
    "--robot",
    "robots",
    multiple=True,
    help="Robot to compile for (repeatable): a name or PATH/robot.yaml with a fit catalogue; "
    "default: every built-in robot with one.",
)
@click.option(
    "--effects",
    default="M,G,S",
    show_default=True,
    help="Effects the fit's simulator runs with (identify sim's --effects, plus S for its "
    "sensors); MuJoCo Warp needs M.",
)
@click.option("--device", help="Warp device, e.g. cuda:0 or cpu (default: Warp's default).")
def warp_warm_up_command(robots: tuple[str, ...], effects: str, device: str | None) -> None:
    """Compile every kernel a fit on MuJoCo Warp uses into the persistent kernel cache.

    One tiny batched rollout per robot; a second warm-up only loads the kernels.
    """
    from zmpkit.simfit.warp_warm_up import warm_up_warp

    names = robots or tuple(r for r in robots_that("fit") if missing_reason(r) is None)
    result = warm_up_warp([get_robot(n, needs="fit") for n in names], effects, device)
    for robot in result.robots:
        if robot.skipped is None:
            click.echo(f"{robot.robot}: {robot.seconds:.1f} s")
        else:
            click.echo(f"{robot.robot}: skipped ({robot.skipped})")
    new = result.files_after - result.files_before
    click.echo(
        f"kernel cache: {result.cache_dir} ({result.files_after} files, {new} new); "
        f"device {result.device}; took {result.seconds:.1f} s"
    )
