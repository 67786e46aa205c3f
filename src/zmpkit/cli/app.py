"""The ``zmpkit`` command's root group and entry point; subcommands live beside it.

Thin by design: each command parses its options, builds a configuration, calls one library
function and prints where the results are. Every user mistake (bad file, bad option) ends with
one line on stderr and exit code 2.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

import click

from zmpkit import __version__
from zmpkit.errors import ZmpkitError

__all__ = ["EXIT_USAGE", "ROBOT_CHOICES", "cli", "format_or_undefined", "main"]

ROBOT_CHOICES = ("teo",)
EXIT_USAGE = 2


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "--version", prog_name="zmpkit")
def cli() -> None:
    """zmpkit: measure, model and compensate the gap between the LIPM and the real robot."""


def format_or_undefined(value: float | None, spec: str) -> str:
    """``value`` formatted, or "undefined" (e.g. a walk too short to fit its speed)."""
    return "undefined" if value is None else format(value, spec)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI and return its exit code (tests call this with ``argv``)."""
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        result = cli.main(args=args, prog_name="zmpkit", standalone_mode=False)
    except click.ClickException as exc:
        exc.show()
        return exc.exit_code
    except click.Abort:
        click.echo("zmpkit: aborted", err=True)
        return 130
    except ZmpkitError as exc:
        click.echo(f"zmpkit: error: {exc}", err=True)
        return EXIT_USAGE
    return result if isinstance(result, int) else 0
