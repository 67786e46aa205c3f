"""Option types for physical quantities: a finite number within its valid range.

``click.FloatRange`` lets NaN through (every comparison with NaN is false) and prints no
unit; :class:`Bounded` refuses any non-finite value and names the valid range with its unit,
so ``--speed -1`` ends with one line: ``Invalid value for '--speed': must lie in [0, 0.24]
m/s, got -1``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from zmpkit.analysis.report_files import DEFAULT_REPORT_FORMAT, REPORT_FORMATS
from zmpkit.experiments import MAX_WORKERS

_F = TypeVar("_F", bound=Callable[..., Any])
"""A click command function (a decorator returns it decorated)."""

__all__ = [
    "MAX_WORKERS",
    "SEED",
    "WORKERS",
    "Bounded",
    "BoundedInt",
    "report_option",
]


def _number(text: float | str) -> str:
    return f"{text:g}" if isinstance(text, float) else str(text)


class Bounded(click.ParamType):
    """A finite float in ``[low, high]`` [unit]; either bound may be open (``None``).

    Args:
        low: smallest valid value, or None for no lower bound.
        high: largest valid value, or None for no upper bound.
        unit: the unit named in messages, e.g. ``"m/s"``.
        low_open: ``low`` itself is invalid (e.g. a duration > 0).
    """

    name = "float"

    def __init__(
        self, low: float | None, high: float | None, unit: str = "", *, low_open: bool = False
    ) -> None:
        self.low, self.high, self.unit, self.low_open = low, high, unit, low_open

    @property
    def valid(self) -> str:
        """The valid range as text, e.g. ``(0, 600] s``."""
        left = "(" if self.low_open or self.low is None else "["
        low = "-inf" if self.low is None else _number(self.low)
        high = "inf)" if self.high is None else f"{_number(self.high)}]"
        return f"{left}{low}, {high}" + (f" {self.unit}" if self.unit else "")

    def convert(
        self, value: object, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        """Parse ``value`` and check it; fail with one line naming the valid range."""
        try:
            x = float(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            self.fail(f"expected a number in {self.valid}, got {str(value)[:40]!r}", param, ctx)
        too_low = self.low is not None and (x <= self.low if self.low_open else x < self.low)
        too_high = self.high is not None and x > self.high
        if not math.isfinite(x) or too_low or too_high:
            self.fail(f"must lie in {self.valid}, got {x:g}", param, ctx)
        return x


class BoundedInt(click.ParamType):
    """An integer in ``[low, high]`` (counts: workers, generations, seeds)."""

    name = "integer"

    def __init__(self, low: int, high: int | None = None) -> None:
        self.low, self.high = low, high

    def convert(
        self, value: object, param: click.Parameter | None, ctx: click.Context | None
    ) -> int:
        """Parse ``value`` and check it; fail with one line naming the valid range."""
        valid = f"[{self.low}, {'inf)' if self.high is None else f'{self.high}]'}"
        try:
            n = int(str(value), 10)
        except ValueError:
            self.fail(f"expected an integer in {valid}, got {str(value)[:40]!r}", param, ctx)
        if n < self.low or (self.high is not None and n > self.high):
            self.fail(f"must lie in {valid}, got {n}", param, ctx)
        return n


WORKERS = BoundedInt(1, MAX_WORKERS)
"""``--workers``: 1 to :data:`MAX_WORKERS`."""
SEED = BoundedInt(0, 2**63 - 1)
"""``--seed``: a non-negative integer."""


def report_option(function: _F) -> _F:
    """``--report html|md|both``: the report's format (html: one self-contained page)."""
    return click.option(
        "--report",
        "report_format",
        type=click.Choice(REPORT_FORMATS),
        default=DEFAULT_REPORT_FORMAT,
        show_default=True,
        help="Report format: html (report.html, one self-contained page), md (report.md), both.",
    )(function)


def log_source_options(function: _F) -> _F:
    """``--units PATH`` and ``--time-source header|receive``: how a recorded log is read."""
    units = click.option(
        "--units",
        "units_path",
        type=click.Path(path_type=Path),
        help="Units/frames YAML: axis order, signs, N vs daN, N·m vs dN·m, rad vs deg, "
        "mounting rotation.",
    )
    time_source = click.option(
        "--time-source",
        type=click.Choice(("header", "receive")),
        default="header",
        show_default=True,
        help="Bags and YARP logs: the message header (sender) stamp or the receive time.",
    )
    return units(time_source(function))
