"""The robot registry: built-in robots by name, a user's robot by its ``robot.yaml``.

:func:`get_robot` is the one way into a :class:`~zmpkit.robots.robot.Robot`: a registry name
(:func:`robot_names`) or the path of a ``robot.yaml`` (:mod:`zmpkit.robots.robot_file`).
Each built-in robot lives in its own folder (``robots/<name>/``: model, truth, preset).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from zmpkit.errors import ParameterError
from zmpkit.robots.nao.preset import NAO
from zmpkit.robots.robot import Robot
from zmpkit.robots.teo.preset import TEO
from zmpkit.robots.user_robot import load_robot_file

__all__ = [
    "DEFAULT_BALANCE_ROBOT",
    "DEFAULT_FIT_ROBOT",
    "DEFAULT_WALK_ROBOT",
    "get_robot",
    "robot_names",
    "robots_that",
]

DEFAULT_BALANCE_ROBOT = "teo"
"""The robot of the balance commands when none is given (paper A's)."""
DEFAULT_WALK_ROBOT = "nao"
"""The robot of the walking commands when none is given (paper B's)."""
DEFAULT_FIT_ROBOT = "nao"
"""The robot of ``zmpkit identify sim`` when none is given."""
ROBOT_FILE_SUFFIXES = (".yaml", ".yml")


@cache
def _builtin() -> dict[str, Robot]:
    return {robot.name: robot for robot in (NAO, TEO)}


def robot_names() -> tuple[str, ...]:
    """The built-in robots' names, sorted."""
    return tuple(sorted(_builtin()))


def robots_that(has: str) -> tuple[str, ...]:
    """Built-in robots with a ``"balance"`` model, ``"walking"`` defaults or a ``"fit"``."""
    return tuple(name for name, robot in sorted(_builtin().items()) if getattr(robot, has))


_NEEDS = {
    "balance": "it has no balance model",
    "walking": "it has no walking defaults",
    "fit": "it has no simulator-fit catalogue",
}


def get_robot(name_or_path: str | Path | Robot, needs: str | None = None) -> Robot:
    """The robot named ``name_or_path``, or the one a ``robot.yaml`` file describes.

    Args:
        name_or_path: a built-in name (:func:`robot_names`), a ``robot.yaml`` path, or a
            robot (returned as is).
        needs: ``"balance"``, ``"walking"`` or ``"fit"``: the robot must have it.

    Raises:
        ParameterError: on an unknown name, or a robot without what is needed, naming the
            valid ones: ``robot must be one of nao, teo; got 'asimo' (...)``.
        InputFileError: on a robot file that cannot be read, one line per problem.
    """
    valid = robot_names() if needs is None else robots_that(needs)
    if isinstance(name_or_path, Robot):
        robot = name_or_path
    else:
        text = str(name_or_path)
        builtin = _builtin()
        if text in builtin:
            robot = builtin[text]
        elif Path(text).suffix.lower() in ROBOT_FILE_SUFFIXES:
            robot = _robot_file(str(Path(text).resolve()))
        else:
            raise ParameterError(
                f"robot must be one of {', '.join(valid)}; got {text!r} (or a robot.yaml file)"
            )
    if needs is not None and getattr(robot, needs) is None:
        raise ParameterError(
            f"robot must be one of {', '.join(valid)}; got {robot.name!r} ({_NEEDS[needs]})"
        )
    return robot


@cache
def _robot_file(path: str) -> Robot:
    return load_robot_file(path)
