"""Boundary checks shared by the public constructors and functions.

Each raises :class:`~zmpkit.errors.ParameterError` whose message names the parameter, the
value that came and what was expected.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit.errors import ParameterError

__all__ = [
    "finite",
    "finite_array",
    "in_range",
    "list_some",
    "non_negative",
    "positive",
    "shorten",
]

MAX_ECHO_CHARS = 40
"""Longest piece of a user's input a message repeats (characters)."""


def finite(name: str, value: float) -> float:
    """Return ``value`` as a float, or raise if it is not a finite real number."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a finite real number, got {value!r}") from None
    if not math.isfinite(x):
        raise ParameterError(f"{name} must be finite, got {x}")
    return x


def positive(name: str, value: float, unit: str = "") -> float:
    """Return ``value`` as a float, or raise if it is not finite and > 0."""
    x = finite(name, value)
    if x <= 0.0:
        suffix = f" {unit}" if unit else ""
        raise ParameterError(f"{name} must be > 0{suffix}, got {x}{suffix}")
    return x


def non_negative(name: str, value: float, unit: str = "") -> float:
    """Return ``value`` as a float, or raise if it is not finite and >= 0."""
    x = finite(name, value)
    if x < 0.0:
        suffix = f" {unit}" if unit else ""
        raise ParameterError(f"{name} must be >= 0{suffix}, got {x}{suffix}")
    return x


def in_range(name: str, value: float, low: float, high: float, unit: str = "") -> float:
    """Return ``value`` as a float, or raise if it is outside the closed interval [low, high]."""
    x = finite(name, value)
    if not low <= x <= high:
        suffix = f" {unit}" if unit else ""
        raise ParameterError(f"{name} must lie in [{low}, {high}]{suffix}, got {x}{suffix}")
    return x


def finite_array(
    name: str, value: ArrayLike, shape: tuple[int | None, ...] | None = None
) -> NDArray[np.float64]:
    """Return ``value`` as a float64 array, checking finiteness and (optionally) shape.

    Args:
        name: parameter name used in the message.
        value: anything numpy can turn into a float array.
        shape: expected shape; ``None`` entries match any length.
    """
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an array of real numbers, got {value!r}") from None
    if shape is not None:
        ok = arr.ndim == len(shape) and all(
            want is None or got == want for got, want in zip(arr.shape, shape, strict=True)
        )
        if not ok:
            pretty = "(" + ", ".join("N" if s is None else str(s) for s in shape) + ")"
            raise ParameterError(f"{name} must have shape {pretty}, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise ParameterError(f"{name} must be finite everywhere, got non-finite at index {bad}")
    return arr


def shorten(value: object, limit: int = MAX_ECHO_CHARS) -> str:
    """``repr(value)``, cut to ``limit`` characters with an ellipsis, for an error message."""
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def list_some(names: Sequence[object], shown: int = 5) -> str:
    """The first ``shown`` of ``names`` joined by commas, then how many more there are.

    Keeps a message that lists a file's columns (or any long choice) to one short line.
    """
    items = [str(n) if len(str(n)) <= MAX_ECHO_CHARS else shorten(n) for n in names]
    head = ", ".join(items[:shown])
    rest = len(items) - shown
    return f"{head} and {rest} more" if rest > 0 else head
