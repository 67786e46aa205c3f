"""Loading YAML files into plain mappings, with errors that name the file and line.

Numbers are read as YAML 1.2 reads them: ``3e-2`` and ``1E5`` are floats (PyYAML's YAML 1.1
rules read an exponent without a dot as a string), see :class:`Yaml12Loader`.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal, overload

import yaml

from zmpkit._validate import shorten
from zmpkit.errors import InputFileError

__all__ = [
    "Yaml12Loader",
    "load_yaml",
    "read_yaml_mapping",
    "require_number",
    "require_vector",
    "yaml_error",
]

_FLOAT_TAG = "tag:yaml.org,2002:float"
_YAML12_FLOAT = re.compile(
    r"""^(?:[-+]?(?:[0-9]+\.[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?
    |[-+]?[0-9]+[eE][-+]?[0-9]+
    |[-+]?\.(?:inf|Inf|INF)
    |\.(?:nan|NaN|NAN))$""",
    re.VERBOSE,
)


class Yaml12Loader(yaml.SafeLoader):
    """PyYAML's safe loader with YAML 1.2 (core schema) floats.

    ``3e-2``, ``-1E5`` and ``2.5e+3`` are floats, as a user writing a number expects (YAML
    1.1, which PyYAML follows, needs a dot in the mantissa: ``3.0e-2``). Integers, booleans,
    null and everything else are read as by :class:`yaml.SafeLoader`.
    """


Yaml12Loader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != _FLOAT_TAG]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
Yaml12Loader.add_implicit_resolver(_FLOAT_TAG, _YAML12_FLOAT, list("-+0123456789."))


def load_yaml(text: str) -> Any:
    """Parse YAML ``text`` safely, with YAML 1.2 floats (:class:`Yaml12Loader`)."""
    return yaml.load(text, Loader=Yaml12Loader)  # a SafeLoader subclass: safe


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
        data = load_yaml(text)
    except yaml.YAMLError as exc:
        raise yaml_error(path, exc) from None
    if not isinstance(data, Mapping):
        got = "an empty file" if data is None else f"a {type(data).__name__}"
        raise InputFileError(path, f"expected a mapping at the top level, got {got}")
    return data


def yaml_error(path: Path, exc: yaml.YAMLError) -> InputFileError:
    """One-line error for a YAML syntax error: the file, the line and the problem."""
    mark = getattr(exc, "problem_mark", None)
    row = mark.line + 1 if mark is not None else None
    problem = getattr(exc, "problem", None) or "invalid YAML"
    return InputFileError(path, f"invalid YAML: {problem}", row=row)


def require_number(path: Path, field: str, value: object) -> float:
    """Return ``value`` as a finite float or raise an error naming ``field``."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputFileError(path, f"field '{field}' must be a number, got {shorten(value)}")
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
            path, f"field '{field}' must be a list of {length} numbers, got {shorten(value)}"
        )
    return tuple(require_number(path, f"{field}[{i}]", v) for i, v in enumerate(value))
