"""``zmpkit robot``: list the built-in robots, write a robot.yaml for a model, check one."""

from __future__ import annotations

from pathlib import Path

import click

from zmpkit.errors import ZmpkitError
from zmpkit.experiments.walking_posture import choose_walking_posture
from zmpkit.robots.registry import get_robot, missing_reason, robot_names, robots_that
from zmpkit.robots.robot_check import check_robot
from zmpkit.robots.robot_file_reader import read_robot_file
from zmpkit.robots.robot_init import append_walking_keys, write_robot_file
from zmpkit.robots.truth_template import write_truth_template

__all__ = [
    "robot_check_command",
    "robot_group",
    "robot_init_command",
    "robot_list_command",
    "robot_truth_init_command",
]


@click.group("robot")
def robot_group() -> None:
    """Robots: the built-in ones, and your own MJCF or URDF through a robot.yaml."""


@robot_group.command("list")
def robot_list_command() -> None:
    """List the built-in robots and what each can run (and how to install a missing one)."""
    for name in robot_names():
        can = ", ".join(x for x in ("balance", "walking", "fit") if name in robots_that(x))
        reason = missing_reason(name)
        if reason is None:
            click.echo(f"{name}: {get_robot(name).summary} [{can}]")
        else:
            click.echo(f"{name}: not available, {reason} [{can}]")


@robot_group.command("init")
@click.argument("model", type=click.Path(path_type=Path))
@click.option(
    "--out", type=click.Path(path_type=Path), required=True, help="The robot.yaml to write."
)
@click.option(
    "--package",
    "packages",
    multiple=True,
    metavar="NAME=DIR",
    help="Folder of a ROS package the URDF's package:// URIs name (repeatable; default: the "
    "nearest folder of that name above the model).",
)
def robot_init_command(model: Path, out: Path, packages: tuple[str, ...]) -> None:
    """Write a first robot.yaml for MODEL (MJCF or URDF): feet, legs, IMU guessed."""
    folders = {}
    for text in packages:
        name, sep, folder = text.partition("=")
        if not sep or not name or not folder:
            raise click.BadParameter(f"expected NAME=DIR, got {text!r}", param_hint="'--package'")
        folders[name] = Path(folder)
    guess = write_robot_file(model, out, folders)
    for note in guess.notes:
        click.echo(f"guessed {note}")
    _choose_walking_posture(out)
    click.echo(f"wrote {out}; check the guesses, then: zmpkit robot check {out}")


def _choose_walking_posture(out: Path) -> None:
    """Probe the default walking posture of the robot ``out`` describes; write a better one.

    A robot file that does not build, or a robot that cannot walk, is left to
    ``zmpkit robot check`` to explain.
    """
    try:
        robot = get_robot(str(out))
    except ZmpkitError:
        return
    if robot.walking is None:
        return
    choice = choose_walking_posture(robot, read_robot_file(out))
    default = choice.default
    if choice.chosen is not None:
        posture = choice.chosen.posture
        assert default is not None  # a posture is chosen only after the default's probe
        note = (
            f"{posture.describe()} (upright and centred: {default.describe()}; this posture: "
            f"{choice.chosen.describe()})"
        )
        keys = {
            "torso_pitch": posture.torso_pitch_rad,
            "crouch": posture.crouch,
            "zmp_forward": posture.zmp_forward_m,
        }
        append_walking_keys(out, keys, note)
        click.echo(f"guessed walking posture: {note}")
    elif default is not None and not default.realisable:
        click.echo(
            f"walking: upright and centred, {default.describe()}, and none of the "
            f"{choice.tried} postures tried keeps its joints off their limits: `zmpkit walk` "
            "will refuse this robot"
        )


@robot_group.group("truth")
def robot_truth_group() -> None:
    """The truth of your robot's effects (motors, gears, links): what the simulator plays."""


@robot_truth_group.command("init")
@click.argument("robot_file", type=click.Path(path_type=Path))
@click.option(
    "--out", type=click.Path(path_type=Path), required=True, help="The truth YAML to write."
)
def robot_truth_init_command(robot_file: Path, out: Path) -> None:
    """Write a first truth for ROBOT_FILE's leg drives: what the model states, the rest ASSUMED."""
    template = write_truth_template(robot_file, out)
    click.echo(
        f"wrote {out}: {template.from_model} values from the model, {template.assumed} ASSUMED "
        "(marked in the file: replace them with your robot's)"
    )
    click.echo(f"add `truth: {out}` to {robot_file} (a path relative to it) to simulate them")


@robot_group.command("check")
@click.argument("robot_file", type=click.Path(path_type=Path))
@click.option("--stand", type=float, default=2.0, show_default=True, help="Standing time [s].")
def robot_check_command(robot_file: Path, stand: float) -> None:
    """Load ROBOT_FILE (robot.yaml or a built-in name), stand it and compare its ZMPs."""
    result = check_robot(get_robot(str(robot_file)), stand_s=stand)
    for line in result.lines():
        click.echo(line)
    if not result.ok:
        raise click.exceptions.Exit(1)
