"""The ``--robot NAME|PATH/robot.yaml`` option of the commands that run a robot."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

from zmpkit.robots.registry import get_robot, robot_names, robots_that

__all__ = ["robot_option"]

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
