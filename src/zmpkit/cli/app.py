"""The ``zmpkit`` command's root group and entry point; subcommands live beside it.

Thin by design: each command parses its options, builds a configuration, calls one library
function and prints where the results are. Every user mistake (bad file, bad option) ends with
one line on stderr per problem (a robot file with three problems: three lines) and exit code 2.
"""

from __future__ import annotations

import importlib
import sys
import warnings
from collections.abc import Sequence
from typing import TextIO

import click

from zmpkit import __version__
from zmpkit.errors import ZmpkitError, ZmpkitWarning, problem_lines

__all__ = [
    "COMMANDS",
    "EXIT_USAGE",
    "SIMULATING",
    "LazyGroup",
    "cli",
    "format_or_undefined",
    "main",
]

EXIT_USAGE = 2
_PYTHON_SHOWWARNING = warnings.showwarning


COMMANDS: dict[str, tuple[str, str]] = {
    "balance": (
        "zmpkit.cli.balance:balance_command",
        "Paper A end to end: LIPM steps, DLIPM identification, scheduled controller, Table 1.",
    ),
    "demo": (
        "zmpkit.cli.demo:demo_command",
        "Run the main job on the built-in virtual robot and write a report to --out.",
    ),
    "identify": (
        "zmpkit.cli.identify:identify_group",
        "Identify models of the robot from recorded data.",
    ),
    "robot": (
        "zmpkit.cli.robot:robot_group",
        "Robots: the built-in ones, and your own MJCF or URDF through a robot.yaml.",
    ),
    "sim": (
        "zmpkit.cli.sim:sim_group",
        "Run experiments on a virtual robot and write their datasets and analyses.",
    ),
    "walk": (
        "zmpkit.cli.walk:walk_group",
        "Walk the virtual robot with the 3D-LIPM pattern (paper B) and analyse the walk.",
    ),
    "warp": (
        "zmpkit.cli.warp:warp_group",
        "MuJoCo Warp (the fit's --backend warp): its kernel cache and warm-up.",
    ),
    "zmp": (
        "zmpkit.cli.zmp:zmp_command",
        "ZMP of a recorded force-torque LOG; writes zmp.csv and zmp.png.",
    ),
}
"""Subcommand -> ("module:attribute", one-line help). The module is imported only when the
subcommand runs (or shows its own help), so ``zmpkit --help`` needs no physics engine."""
SIMULATING = frozenset({"balance", "demo", "identify", "sim", "walk", "warp"})
"""Subcommands that run MuJoCo: their MuJoCo warnings go to logging
(:func:`~zmpkit.sim.mujoco_messages.route_mujoco_warnings`), not to the terminal and
``MUJOCO_LOG.TXT``; a diverging candidate is counted from the warning counters."""


class LazyGroup(click.Group):
    """A group whose subcommands live in modules imported on first use (:data:`COMMANDS`)."""

    def __init__(self, *args: object, lazy: dict[str, tuple[str, str]], **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.lazy = lazy

    def list_commands(self, ctx: click.Context) -> list[str]:
        """Every subcommand's name, without importing any."""
        return sorted({*super().list_commands(ctx), *self.lazy})

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        """The subcommand ``cmd_name``, importing its module the first time."""
        if cmd_name not in self.lazy:
            return super().get_command(ctx, cmd_name)
        module, attribute = self.lazy[cmd_name][0].split(":")
        if cmd_name in SIMULATING:
            from zmpkit.sim.mujoco_messages import route_mujoco_warnings

            route_mujoco_warnings()
        command = getattr(importlib.import_module(module), attribute)
        if not isinstance(command, click.Command):
            raise TypeError(f"{module}:{attribute} is not a click command")
        return command

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """The help's command list, from the one-line helps of :data:`COMMANDS`."""
        rows = [(name, self.lazy[name][1]) for name in sorted(self.lazy)]
        with formatter.section("Commands"):
            formatter.write_dl(rows)


@click.group(
    cls=LazyGroup,
    lazy=COMMANDS,
    context_settings={"help_option_names": ["-h", "--help"]},
)
@click.version_option(__version__, "--version", prog_name="zmpkit")
def cli() -> None:
    """zmpkit: measure, model and compensate the gap between the LIPM and the real robot."""


def format_or_undefined(value: float | None, spec: str) -> str:
    """``value`` formatted, or "undefined" (e.g. a walk too short to fit its speed)."""
    return "undefined" if value is None else format(value, spec)


def _usage_line(exc: click.UsageError) -> str:
    """A usage error as one line: the command, what was wrong, where the help is."""
    message = " ".join(exc.format_message().split())
    if exc.ctx is None:
        return message
    path = exc.ctx.command_path
    return f"{path}: {message} (see '{path} --help')"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI and return its exit code (tests call this with ``argv``)."""
    args = list(sys.argv[1:] if argv is None else argv)
    with warnings.catch_warnings():
        warnings.simplefilter("always", ZmpkitWarning)
        warnings.showwarning = _show_warning
        return _run(args)


def _show_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """Print a zmpkit warning as one line (``zmpkit: warning: ...``); others as Python does."""
    if issubclass(category, ZmpkitWarning):
        click.echo(f"zmpkit: warning: {message}", err=True)
    else:
        _PYTHON_SHOWWARNING(message, category, filename, lineno, file, line)


def _run(args: list[str]) -> int:
    try:
        result = cli.main(args=args, prog_name="zmpkit", standalone_mode=False)
    except click.UsageError as exc:
        click.echo(f"zmpkit: error: {_usage_line(exc)}", err=True)
        return EXIT_USAGE
    except click.ClickException as exc:
        click.echo(f"zmpkit: error: {exc.format_message()}", err=True)
        return exc.exit_code
    except click.Abort:
        click.echo("zmpkit: aborted", err=True)
        return 130
    except ZmpkitError as exc:
        for line in problem_lines(exc):
            click.echo(f"zmpkit: error: {line}", err=True)
        return EXIT_USAGE
    return result if isinstance(result, int) else 0
