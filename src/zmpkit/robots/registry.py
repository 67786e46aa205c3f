"""The robot registry: built-in robots by name, a user's robot by its ``robot.yaml``.

:func:`get_robot` is the one way into a :class:`~zmpkit.robots.robot.Robot`: a registry name
(:func:`robot_names`) or the path of a ``robot.yaml`` (:mod:`zmpkit.robots.robot_file`).
Each built-in robot lives in its own folder (``robots/<name>/``: model, truth, preset) and is
registered as a :class:`RegistryEntry`: what it can run is known without loading it, and a
robot whose model comes from an optional package says so (:func:`missing_reason`) instead of
failing when the registry is listed.

A robot is a value that code below the pipelines takes as it is; it crosses into a worker
process as its :attr:`~zmpkit.robots.robot.Robot.source` (the registry registers this with
:mod:`copyreg`), and the worker resolves it once: :func:`get_robot` gives each built-in robot
and each robot file once per process.
"""

from __future__ import annotations

import copyreg
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from zmpkit.errors import ParameterError, ZmpkitError
from zmpkit.robots.nao.preset import NAO
from zmpkit.robots.op3.preset import OP3_CAPABILITIES, op3_missing_reason, op3_robot
from zmpkit.robots.robot import Robot
from zmpkit.robots.robot_file_reader import read_robot_file
from zmpkit.robots.teo.preset import TEO
from zmpkit.robots.user_robot import load_robot_file

__all__ = [
    "DEFAULT_BALANCE_ROBOT",
    "DEFAULT_FIT_ROBOT",
    "DEFAULT_WALK_ROBOT",
    "RegistryEntry",
    "get_robot",
    "missing_reason",
    "robot_names",
    "robot_reference",
    "robots_that",
]

DEFAULT_BALANCE_ROBOT = "teo"
"""The robot of the balance commands when none is given (paper A's)."""
DEFAULT_WALK_ROBOT = "nao"
"""The robot of the walking commands when none is given (paper B's)."""
DEFAULT_FIT_ROBOT = "nao"
"""The robot of ``zmpkit identify sim`` when none is given."""
ROBOT_FILE_SUFFIXES = (".yaml", ".yml")


CAPABILITIES = ("balance", "walking", "fit")
"""What a robot may have: a balance model, walking defaults, a simulator-fit catalogue."""


@dataclass(frozen=True)
class RegistryEntry:
    """A built-in robot as the registry holds it, loaded on first use.

    Attributes:
        name: the registry name (``--robot NAME``).
        load: builds the robot.
        capabilities: what it has, among :data:`CAPABILITIES`.
        missing: why it cannot be loaded here (an optional package absent), or None.
    """

    name: str
    load: Callable[[], Robot]
    capabilities: tuple[str, ...]
    missing: Callable[[], str | None]


def _ready(robot: Robot) -> RegistryEntry:
    has = tuple(c for c in CAPABILITIES if getattr(robot, c) is not None)
    return RegistryEntry(robot.name, lambda: robot, has, lambda: None)


@cache
def _entries() -> dict[str, RegistryEntry]:
    entries = (
        _ready(NAO),
        _ready(TEO),
        RegistryEntry("op3", op3_robot, OP3_CAPABILITIES, op3_missing_reason),
    )
    return {entry.name: entry for entry in entries}


def robot_names() -> tuple[str, ...]:
    """The built-in robots' names, sorted (those whose optional model is absent too)."""
    return tuple(sorted(_entries()))


def robots_that(has: str) -> tuple[str, ...]:
    """Built-in robots with a ``"balance"`` model, ``"walking"`` defaults or a ``"fit"``."""
    return tuple(name for name, e in sorted(_entries().items()) if has in e.capabilities)


def missing_reason(name: str) -> str | None:
    """Why the built-in robot ``name`` cannot be loaded here, or None when it can.

    The reason names what to install: ``its model is not installed: pip install ...``.

    Raises:
        ParameterError: on an unknown name.
    """
    entries = _entries()
    if name not in entries:
        raise ParameterError(f"robot must be one of {', '.join(robot_names())}; got {name!r}")
    return entries[name].missing()


_NEEDS = {
    "balance": "it has no balance model",
    "walking": "it has no walking defaults",
    "fit": "it has no simulator-fit catalogue; a robot.yaml gets one from a `truth:` file, "
    "which `zmpkit robot truth init robot.yaml --out truth.yaml` starts",
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
            A built-in robot whose optional model is not installed names how to install it.
        InputFileError: on a robot file that cannot be read, one line per problem.
    """
    valid = robot_names() if needs is None else robots_that(needs)
    if isinstance(name_or_path, Robot):
        robot = name_or_path
    else:
        text = str(name_or_path)
        entries = _entries()
        if text in entries:
            robot = entries[text].load()
        elif Path(text).suffix.lower() in ROBOT_FILE_SUFFIXES:
            path = Path(text).resolve()
            robot = _robot_file(str(path), tuple(_stamp(p) for p in _sources(path)))
        else:
            raise ParameterError(
                f"robot must be one of {', '.join(valid)}; got {text!r} (or a robot.yaml file)"
            )
    if needs is not None and getattr(robot, needs) is None:
        raise ParameterError(
            f"robot must be one of {', '.join(valid)}; got {robot.name!r} ({_NEEDS[needs]})"
        )
    return robot


def robot_reference(name_or_path: str | Path) -> str:
    """How a dataset records a robot: a built-in robot's name, a robot file's absolute path.

    A ``robot.yaml`` given relative to the working folder is found again from any folder.
    """
    text = str(name_or_path)
    if text in _entries() or Path(text).suffix.lower() not in ROBOT_FILE_SUFFIXES:
        return text
    return str(Path(text).resolve())


def _sources(path: Path) -> tuple[Path, ...]:
    """The robot file and the model and truth files it names (itself alone if unreadable)."""
    try:
        file = read_robot_file(path)
    except ZmpkitError:
        return (path,)
    return tuple(p for p in (path, file.model, file.truth) if p is not None)


def _stamp(path: Path) -> tuple[int, int]:
    """The robot file's modification time [ns] and size [B] (0, 0 when it is missing)."""
    try:
        stat = path.stat()
    except OSError:
        return 0, 0
    return stat.st_mtime_ns, stat.st_size


@cache
def _robot_file(path: str, stamps: tuple[tuple[int, int], ...]) -> Robot:
    """The robot of the file at ``path``, built once per version of the files it rests on.

    ``stamps`` are those of the robot, model and truth files: an edited one is read again.
    """
    del stamps  # part of the cache's key only
    return load_robot_file(path)


def _by_source(robot: Robot) -> tuple[Callable[[str], Robot], tuple[str]]:
    """How a robot is pickled: as its source, which :func:`get_robot` resolves again."""
    return get_robot, (robot.source,)


copyreg.pickle(Robot, _by_source)
