"""The verdict of a balance run: paper A's bars per plane, met, missed or undefined, and why.

Bars (:mod:`zmpkit.analysis.balance_targets`), per plane:

- ``far error ratio``: |DLIPM error| / |LIPM error| at the farthest target ≤ 0.20 (paper A:
  2.0 / 11.6 = 0.17);
- ``mean error ratio``: mean |DLIPM error| / mean |LIPM error| over the targets ≠ 0 ≤ 1/3.

A bar is *undefined* when a value it needs is: the verdict then names the trials that did
not settle and why ("did not settle within H s (drift X mm/s)", "ended tipping …"), or the
LIPM errors too small to measure a ratio of (within two standard errors of their settled
values, :data:`~zmpkit.analysis.balance_targets.RESOLVED_SE`).
Warnings, which do not decide a bar but belong to the verdict: targets outside the range the
error model was fitted on (the controllers extrapolated it), and unsettled trials elsewhere.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from zmpkit.analysis.balance_targets import (
    FAR_TARGET_RATIO_MAX,
    MEAN_ERROR_RATIO_MAX,
    balance_targets,
)
from zmpkit.analysis.table1 import Table1Row

__all__ = ["BAR_STATES", "Bar", "PlaneVerdict", "plane_verdict"]

BAR_STATES = ("met", "missed", "undefined")
"""What a bar can be."""


@dataclass(frozen=True)
class Bar:
    """One bar of one plane.

    Attributes:
        name: ``"far error ratio"`` or ``"mean error ratio"``.
        value: the measured ratio [-]; None if undefined.
        limit: the bar, value ≤ limit [-].
        state: one of :data:`BAR_STATES`.
        why: for an undefined bar, what is missing and why; empty otherwise.
    """

    name: str
    value: float | None
    limit: float
    state: str
    why: str = ""

    def line(self) -> str:
        """The bar as one line of text."""
        value = "undefined" if self.value is None else f"{self.value:.3g}"
        why = f": {self.why}" if self.why else ""
        return f"{self.name} {value} (bar ≤ {self.limit:.2f}): {self.state}{why}"


@dataclass(frozen=True)
class PlaneVerdict:
    """The bars and warnings of one plane.

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        bars: the plane's bars.
        warnings: extrapolated targets and unsettled trials not already named by a bar.
    """

    plane: str
    bars: tuple[Bar, ...]
    warnings: tuple[str, ...]

    @property
    def met(self) -> bool:
        """Whether every bar was met."""
        return all(b.state == "met" for b in self.bars)

    def lines(self) -> list[str]:
        """The verdict as lines of text."""
        head = f"{self.plane}: {'all bars met' if self.met else 'bars not all met'}"
        return [
            head,
            *(f"  {b.line()}" for b in self.bars),
            *(f"  warning: {w}" for w in self.warnings),
        ]


def _state(value: float | None, limit: float) -> str:
    if value is None:
        return "undefined"
    return "met" if value <= limit else "missed"


def _why(rows: Sequence[Table1Row]) -> str:
    """Why the error of these rows is undefined: their unsettled trials."""
    reasons = [
        f"{name.upper()} at {row.zmp_ref:g} m {outcome.unsettled_text()}"
        for row in rows
        for name, outcome in (("lipm", row.lipm), ("dlipm", row.dlipm))
        if outcome.error_pct is None
    ]
    return "; ".join(reasons) or "no target ≠ 0"


def plane_verdict(plane: str, rows: Sequence[Table1Row]) -> PlaneVerdict:
    """The verdict of one plane's Table 1 rows."""
    figures = balance_targets(plane, rows)
    far = max(rows, key=lambda r: abs(r.zmp_ref))
    nonzero = [r for r in rows if r.zmp_ref != 0.0]
    far_bar = Bar(
        "far error ratio",
        figures.far_error_ratio,
        FAR_TARGET_RATIO_MAX,
        _state(figures.far_error_ratio, FAR_TARGET_RATIO_MAX),
        "" if figures.far_error_ratio is not None else figures.far_unresolved or _why([far]),
    )
    mean_bar = Bar(
        "mean error ratio",
        figures.mean_error_ratio,
        MEAN_ERROR_RATIO_MAX,
        _state(figures.mean_error_ratio, MEAN_ERROR_RATIO_MAX),
        "" if figures.mean_error_ratio is not None else figures.mean_unresolved or _why(nonzero),
    )
    return PlaneVerdict(plane, (far_bar, mean_bar), _warnings(rows))


def _warnings(rows: Sequence[Table1Row]) -> tuple[str, ...]:
    out = []
    extrapolated = [r for r in rows if r.extrapolated]
    if extrapolated:
        low, high = extrapolated[0].fit_range_m or (0.0, 0.0)
        targets = ", ".join(f"{r.zmp_ref:g}" for r in extrapolated)
        out.append(
            f"targets {targets} m lie outside the fitted range [{low:.4g}, {high:.4g}] m: "
            "the controllers extrapolated the error model there"
        )
    out += [
        f"linear correction at {r.zmp_ref:g} m {r.linear.unsettled_text()}"
        for r in rows
        if not r.linear.steady.settled
    ]
    return tuple(out)
