"""The ``zmpkit`` command's root group and entry point; subcommands live beside it.

Thin by design: each command parses its options, builds a configuration, calls one library
function and prints where the results are. Every user mistake (bad file, bad option) ends with
one line on stderr and exit code 2.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable, Sequence
from typing import Any, TextIO, TypeVar

import click

from zmpkit import __version__
from zmpkit.errors import ZmpkitError, ZmpkitWarning
from zmpkit.robots.registry import get_robot, robot_names, robots_that

__all__ = ["EXIT_USAGE", "cli", "format_or_undefined", "main", "robot_option"]

EXIT_USAGE = 2
_F = TypeVar("_F", bound=Callable[..., Any])
_NEEDS_TEXT = {
    None: "",
    "balance": " with a balance model",
    "walking": " that walks",
    "fit": " with a fit catalogue",
}


def robot_option(
    default: str | None, needs: str | None = None, help_text: str = "Robot"
) -> Callable[[_F], _F]:
    """The ``--robot NAME|PATH/robot.yaml`` option; its choices come from the registry.

    An unknown robot, or one without what the command ``needs`` (``"balance"``,
    ``"walking"``, ``"fit"``), ends the command with exit 2 and one line naming the valid ones.
    """
    valid = robots_that(needs) if needs else robot_names()

    def check(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
        if value is not None:
            get_robot(value, needs=needs)
        return value

    return click.option(
        "--robot",
        default=default,
        show_default=default is not None,
        callback=check,
        help=f"{help_text}: {', '.join(valid)}, or PATH/robot.yaml (a robot{_NEEDS_TEXT[needs]}).",
    )


_PYTHON_SHOWWARNING = warnings.showwarning


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
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
        click.echo(f"zmpkit: error: {exc}", err=True)
        return EXIT_USAGE
    return result if isinstance(result, int) else 0
