"""Loading YAML files into plain mappings, with errors that name the file and line."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal, overload

import yaml

from zmpkit.errors import InputFileError

__all__ = ["read_yaml_mapping", "require_number", "require_vector"]


def read_yaml_mapping(path: str | Path) -> Mapping[str, Any]:
    """Read a YAML file whose top level must be a mapping.

    Raises:
        InputFileError: the file is missing, is not valid YAML (line given), or is not a mapping.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputFileError(path, "file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(path, f"cannot be read as UTF-8 text ({exc})") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        row = mark.line + 1 if mark is not None else None
        problem = getattr(exc, "problem", None) or "invalid YAML"
        raise InputFileError(path, f"invalid YAML: {problem}", row=row) from None
    if not isinstance(data, Mapping):
        got = "an empty file" if data is None else f"a {type(data).__name__}"
        raise InputFileError(path, f"expected a mapping at the top level, got {got}")
    return data


def require_number(path: Path, field: str, value: object) -> float:
    """Return ``value`` as a finite float or raise an error naming ``field``."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputFileError(path, f"field '{field}' must be a number, got {value!r}")
    x = float(value)
    if x != x or x in (float("inf"), float("-inf")):
        raise InputFileError(path, f"field '{field}' must be finite, got {value!r}")
    return x


@overload
def require_vector(
    path: Path, field: str, value: object, length: Literal[3]
) -> tuple[float, float, float]: ...


@overload
def require_vector(path: Path, field: str, value: object, length: int) -> tuple[float, ...]: ...


def require_vector(path: Path, field: str, value: object, length: int) -> tuple[float, ...]:
    """Return ``value`` as a tuple of ``length`` finite floats or raise naming ``field``."""
    if not isinstance(value, list | tuple) or len(value) != length:
        raise InputFileError(
            path, f"field '{field}' must be a list of {length} numbers, got {value!r}"
        )
    return tuple(require_number(path, f"{field}[{i}]", v) for i, v in enumerate(value))
