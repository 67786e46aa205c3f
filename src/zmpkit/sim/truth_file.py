"""Reading a virtual robot's truth file: the YAML shell every robot's truth shares.

Each robot parses its own sections (its motors, joints, payload, …) with a ``parse(doc,
path)`` function; this module reads the file, checks its top level, turns every parsing
failure into one :class:`~zmpkit.errors.InputFileError` naming the file, and parses the
sections whose layout is common (``flex`` entries).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Generic, Protocol, TypeVar

import yaml

from zmpkit.errors import InputFileError, ZmpkitError
from zmpkit.io.yaml_file import load_yaml, yaml_error
from zmpkit.sim.compliance import FlexJoint

__all__ = [
    "RobotTruth",
    "TruthReader",
    "flex_joint",
    "parse_truth_doc",
    "read_truth_file",
    "section",
    "vector3",
]

T = TypeVar("T")


def read_truth_file(path: Path, parse: Callable[[Mapping[str, Any], Path], T]) -> T:
    """Read the YAML truth file at ``path`` and return ``parse(document, path)``.

    Raises:
        InputFileError: the file cannot be read, is not a mapping, or a field is missing or
            invalid (the parser's error, with the file named).
    """
    try:
        doc = load_yaml(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputFileError(path, "truth file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(path, f"cannot read the truth file as UTF-8 text ({exc})") from None
    except yaml.YAMLError as exc:
        raise yaml_error(path, exc) from None
    return parse_truth_doc(doc, path, parse)


_MAX_REASON_CHARS = 120
"""Longest reason quoted in a truth file's error, so the line stays short [characters]."""


def parse_truth_doc(doc: Any, path: Path, parse: Callable[[Mapping[str, Any], Path], T]) -> T:
    """``parse(doc, path)`` of a truth document already in memory (``path`` names it).

    Raises:
        InputFileError: as :func:`read_truth_file`, naming ``path``.
    """
    if not isinstance(doc, Mapping):
        raise InputFileError(path, "expected a mapping of sections at the top level")
    try:
        return parse(doc, path)
    except InputFileError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError, OverflowError, ZmpkitError) as exc:
        text = str(exc)
        text = text if len(text) <= _MAX_REASON_CHARS else text[: _MAX_REASON_CHARS - 3] + "..."
        raise InputFileError(path, f"invalid truth: {text}") from None


class RobotTruth(Protocol):
    """A robot's truth object: the hidden parameters of its effects, from its truth file.

    Each robot reads its own frozen dataclass (a built-in robot's, or
    :class:`~zmpkit.robots.servo_truth.ServoTruth` and
    :class:`~zmpkit.robots.user_robot.UserTruth` of a robot file); only its robot reads its
    fields. What every one names is the file it came from.
    """

    @property
    def source(self) -> str:
        """The truth file it was read from ("" or a placeholder for one built in memory)."""
        ...


@dataclass(frozen=True)
class TruthReader(Generic[T]):
    """A robot's truth reader: its shipped truth file and the parser of its sections.

    Attributes:
        default_path: the truth file shipped with zmpkit.
        parse: ``parse(document, path)`` → the robot's truth object.
    """

    default_path: Path
    parse: Callable[[Mapping[str, Any], Path], T]

    def load(self, path: str | Path | None = None) -> T:
        """Read a truth file with the layout of the shipped one; ``None`` = the shipped truth.

        Raises:
            InputFileError: if the file cannot be read or a field is missing or invalid.
        """
        file = Path(path) if path is not None else self.default_path
        return read_truth_file(file, self.parse)

    def from_doc(self, doc: Mapping[str, Any], source: str | Path = "<truth document>") -> T:
        """The truth of a document already in memory (the layout of the truth file).

        Raises:
            InputFileError: naming ``source`` if a field is missing or invalid.
        """
        return parse_truth_doc(doc, Path(source), self.parse)


def section(doc: Mapping[str, Any], key: str, path: Path) -> Any:
    """The top-level section ``key`` of a truth document, or an error naming it."""
    if key not in doc:
        raise InputFileError(path, f"missing section '{key}'", column=key)
    return doc[key]


def vector3(values: Iterable[Any]) -> tuple[float, float, float]:
    """A truth file's 3-vector as floats; ValueError (reported naming the file) if not 3 long."""
    x, y, z = (float(v) for v in values)
    return x, y, z


def flex_joint(entry: Mapping[str, Any]) -> FlexJoint:
    """One entry of a truth file's ``flex`` list (a passive compliant joint)."""
    return FlexJoint(
        name=entry["name"],
        body=entry["body"],
        axis=vector3(entry["axis"]),
        anchor=vector3(entry.get("anchor", (0, 0, 0))),
        stiffness=vector3(entry["stiffness"]),
        damping=float(entry.get("damping", 0.0)),
        softening_torque=float(entry.get("softening_torque", 0.0)),
        softening_torque_range=float(entry.get("softening_torque_range", 50.0)),
        softening_stages=int(entry.get("softening_stages", 6)),
    )
