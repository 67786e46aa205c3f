"""The ``--robot NAME|PATH/robot.yaml`` option of the commands that run a robot."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

from zmpkit.robots.registry import get_robot, robot_names, robots_that
from zmpkit.robots.robot import Robot
from zmpkit.robots.robot_check import require_passing_check

__all__ = ["robot_option"]

_F = TypeVar("_F", bound=Callable[..., Any])
_NEEDS_TEXT = {
    None: "",
    "balance": " with a balance model",
    "walking": " that walks",
    "fit": " with a fit catalogue",
}


def robot_option(
    default: str | None,
    needs: str | None = None,
    help_text: str = "Robot",
    *,
    as_robot: bool = False,
) -> Callable[[_F], _F]:
    """The ``--robot NAME|PATH/robot.yaml`` option; its choices come from the registry.

    With ``as_robot`` the command gets the :class:`~zmpkit.robots.robot.Robot` the option
    resolved (once, here, at the boundary), else the text as typed.

    An unknown robot, or one without what the command ``needs`` (``"balance"``,
    ``"walking"``, ``"fit"``), ends the command with exit 2 and one line naming the valid ones.
    A command that runs the robot (``needs`` given) refuses a ``robot.yaml`` whose robot fails
    ``zmpkit robot check`` the same way
    (:func:`~zmpkit.robots.robot_check.require_passing_check`).
    """
    valid = robots_that(needs) if needs else robot_names()

    def check(ctx: click.Context, param: click.Parameter, value: str | None) -> Robot | str | None:
        if value is None:
            return None
        robot = get_robot(value, needs=needs)
        if needs is not None and value not in robot_names():
            require_passing_check(robot, value)
        return robot if as_robot else value

    return click.option(
        "--robot",
        default=default,
        show_default=default is not None,
        callback=check,
        help=f"{help_text}: {', '.join(valid)}, or PATH/robot.yaml (a robot{_NEEDS_TEXT[needs]}).",
    )
