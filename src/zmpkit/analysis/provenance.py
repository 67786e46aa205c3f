"""What made a run: zmpkit version, command line, robot, truth file and its hash, seed, time.

A report a researcher can trust says how to make it again. :func:`capture` is called when a
simulated run ends, with the robot and settings it ran with and the time it started
(:func:`capture_described` when a run's robot is stated in words); it fills in the
rest from the process (``sys.argv``, package versions, the git commit of a source checkout).
The truth file is hashed (SHA-256 of its bytes), so two reports made from truth files of the
same name but different contents can be told apart.
"""

from __future__ import annotations

import hashlib
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Protocol

import zmpkit
from zmpkit.robots.robot import Robot

__all__ = [
    "Provenance",
    "RunSettings",
    "capture",
    "capture_described",
    "capture_run",
    "file_sha256",
]


@dataclass(frozen=True)
class Provenance:
    """Where a run came from.

    Attributes:
        zmpkit_version: the installed version, and the git commit of a source checkout.
        command: the command line that ran, as a shell would take it.
        robot: the robot's :attr:`~zmpkit.robots.robot.Robot.source`: a built-in robot's
            name, a robot file's path.
        truth_file: the virtual robot's truth file (the shipped one when none was given),
            or "" for a run on recorded data.
        truth_sha256: SHA-256 of the truth file's bytes [hex], or "".
        effects: the simulator's effect set, or "".
        seed: the random seed, or None.
        started_utc: when the run started (ISO 8601, UTC).
        wall_time_s: how long it ran [s].
        libraries: versions of the libraries that shape the numbers (MuJoCo, NumPy, SciPy).
        extra: further settings worth stating, as (name, value) pairs.
    """

    zmpkit_version: str
    command: str
    robot: str
    truth_file: str
    truth_sha256: str
    effects: str
    seed: int | None
    started_utc: str
    wall_time_s: float
    libraries: tuple[tuple[str, str], ...]
    extra: tuple[tuple[str, str], ...] = ()

    def rows(self) -> tuple[tuple[str, str], ...]:
        """The provenance as (field, value) rows, in the order a reader wants them."""
        rows = [
            ("zmpkit", self.zmpkit_version),
            ("command", self.command),
            ("robot", self.robot),
            ("truth file", self.truth_file or "none (recorded data)"),
            ("truth SHA-256", self.truth_sha256 or "–"),
            ("effects", self.effects or "–"),
            ("seed", "–" if self.seed is None else str(self.seed)),
            ("started (UTC)", self.started_utc),
            ("wall time", f"{self.wall_time_s:.1f} s"),
            ("libraries", ", ".join(f"{name} {v}" for name, v in self.libraries)),
        ]
        return tuple(rows) + self.extra


def capture(
    *,
    robot: Robot,
    started_s: float,
    truth: str | Path | None = None,
    effects: str = "",
    seed: int | None = None,
    extra: tuple[tuple[str, str], ...] = (),
) -> Provenance:
    """The provenance of a simulated run that started at ``started_s`` and ends now.

    Args:
        robot: the simulated robot (stated by its :attr:`~zmpkit.robots.robot.Robot.source`:
            a built-in robot's name, a robot file's path).
        started_s: the run's start (``time.time()``) [s since the epoch].
        truth: the truth file given, or None for the robot's shipped one.
        effects: the simulator's effect set.
        seed: the random seed.
        extra: further (name, value) settings.
    """
    truth_file = str(Path(truth) if truth is not None else robot.truth.default_path)
    return _provenance(robot.source, truth_file, started_s, effects, seed, extra)


class RunSettings(Protocol):
    """A simulated run's config: the robot, its truth file, effects and seed."""

    @property
    def robot(self) -> Robot:
        """The simulated robot."""
        ...

    @property
    def truth(self) -> str | None:
        """The truth file given, or None for the robot's shipped one."""
        ...

    @property
    def effects(self) -> str:
        """The simulator's effect set."""
        ...

    @property
    def seed(self) -> int:
        """The random seed."""
        ...


def capture_run(
    config: RunSettings, started_s: float, extra: tuple[tuple[str, str], ...] = ()
) -> Provenance:
    """:func:`capture` of a run whose ``config`` names its robot, truth, effects and seed.

    Args:
        config: the run's settings.
        started_s: the run's start (``time.time()``) [s since the epoch].
        extra: further (name, value) settings.
    """
    return capture(
        robot=config.robot,
        started_s=started_s,
        truth=config.truth,
        effects=config.effects,
        seed=config.seed,
        extra=extra,
    )


def capture_described(
    *,
    robot: str,
    started_s: float,
    effects: str = "",
    seed: int | None = None,
    extra: tuple[tuple[str, str], ...] = (),
) -> Provenance:
    """The provenance of a run whose robot is stated in words, with no truth file stated.

    For a run on recorded data (``robot``: where the data came from) or on several robots
    with their shipped truths (``robot``: one robot for balance, another for walking).

    Args:
        robot: what the robot's row states.
        started_s: the run's start (``time.time()``) [s since the epoch].
        effects: the simulator's effect set, or "".
        seed: the random seed, or None.
        extra: further (name, value) settings, e.g. the log and its hash.
    """
    return _provenance(robot, "", started_s, effects, seed, extra)


def _provenance(
    robot: str,
    truth_file: str,
    started_s: float,
    effects: str,
    seed: int | None,
    extra: tuple[tuple[str, str], ...],
) -> Provenance:
    return Provenance(
        zmpkit_version=_zmpkit_version(),
        command=shlex.join(["zmpkit", *sys.argv[1:]]) if _is_cli() else shlex.join(sys.argv),
        robot=robot,
        truth_file=truth_file,
        truth_sha256=file_sha256(Path(truth_file)) if truth_file else "",
        effects=effects,
        seed=seed,
        started_utc=datetime.fromtimestamp(started_s, UTC).isoformat(timespec="seconds"),
        wall_time_s=time.time() - started_s,
        libraries=tuple((name, _version(name)) for name in ("mujoco", "numpy", "scipy")),
        extra=extra,
    )


def file_sha256(path: Path) -> str:
    """SHA-256 of the file's bytes [hex], or "" when it cannot be read."""
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return ""


def _is_cli() -> bool:
    return Path(sys.argv[0]).name in {"zmpkit", "__main__.py"} if sys.argv else False


def _zmpkit_version() -> str:
    commit = _git_commit(Path(zmpkit.__file__).resolve().parent)
    return f"{zmpkit.__version__} (git {commit})" if commit else zmpkit.__version__


def _git_commit(folder: Path) -> str:
    """The checkout's short commit, with ``+dirty`` for local changes; "" outside git."""
    try:
        commit = subprocess.run(
            ["git", "-C", str(folder), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "-C", str(folder), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""
    return f"{commit}+dirty" if dirty else commit


def _version(package: str) -> str:
    try:
        return version(package)
    except PackageNotFoundError:
        return "?"
