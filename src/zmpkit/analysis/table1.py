"""Writing paper A's Table 1 (LIPM vs DLIPM per target) as CSV and as a Markdown table.

The first columns are those of earlier versions, unchanged; then, per controller, how its
trial ended (:data:`STATUS_COLUMNS`): its status (``settled``, ``drifting``,
``oscillating``, ``short``, ``tipping``), its hold [s], its drift rate at the end if
unsettled [mm/s] and the error over its last second [%]; and ``extrapolated`` (1: the
target lies outside the range of measured ZMPs the error model was fitted on, so the
controllers ran the model beyond its data). Last, :data:`FEEDBACK_COLUMNS`: the same
measures for the LIPM with a PI on the measured ZMP (``lipm_pid_*``) and the DLIPM with
that PI (``dlipm_fb_*``), empty unless the run had ``--dlipm-feedback``; then
:data:`ABSOLUTE_COLUMNS`: each controller's settled error in mm (measured − target), which
at a small target says more than the percentage.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from zmpkit.analysis.balance_validation import ControllerOutcome
from zmpkit.control.schedule import EXTRAPOLATION_TOLERANCE_M

__all__ = [
    "ABSOLUTE_COLUMNS",
    "BASE_COLUMNS",
    "FEEDBACK_COLUMNS",
    "STATUS_COLUMNS",
    "TABLE1_COLUMNS",
    "Table1Row",
    "table1_markdown",
    "unsettled_lines",
    "write_table1_csv",
]

TABLE1_COLUMNS: tuple[str, ...] = (
    "plane",
    "zmp_ref",
    "lipm_zmp",
    "lipm_error_pct",
    "dlipm_zmp",
    "dlipm_error_pct",
    "lipm_overshoot_pct",
    "dlipm_overshoot_pct",
    "lipm_settling_s",
    "dlipm_settling_s",
    "linear_zmp",
    "linear_error_pct",
    "linear_overshoot_pct",
    "linear_settling_s",
    "lipm_rms_oscillation_m",
    "dlipm_rms_oscillation_m",
    "fitted_on",
)
_CONTROLLERS = ("lipm", "dlipm", "linear")
_STATUS_FIELDS = ("status", "hold_s", "drift_mm_s", "end_error_pct")
STATUS_COLUMNS = (
    *(f"{c}_{name}" for c in _CONTROLLERS for name in _STATUS_FIELDS),
    "extrapolated",
)
"""Columns after :data:`BASE_COLUMNS`: how each controller's trial ended, extrapolation."""
BASE_COLUMNS = TABLE1_COLUMNS
_FEEDBACK_CONTROLLERS = ("lipm_pid", "dlipm_fb")
_MEASURES = ("zmp", "error_pct", "overshoot_pct", "settling_s")
FEEDBACK_COLUMNS = tuple(
    f"{c}_{name}" for c in _FEEDBACK_CONTROLLERS for name in (*_MEASURES, *_STATUS_FIELDS)
)
"""Columns after :data:`STATUS_COLUMNS`: LIPM+PID and DLIPM+feedback, when they ran."""
ABSOLUTE_COLUMNS = tuple(f"{c}_error_mm" for c in (*_CONTROLLERS, *_FEEDBACK_CONTROLLERS))
"""Last columns: each controller's settled error, measured − target [mm]."""
TABLE1_COLUMNS = BASE_COLUMNS + STATUS_COLUMNS + FEEDBACK_COLUMNS + ABSOLUTE_COLUMNS


@dataclass(frozen=True)
class Table1Row:
    """One target: the three controllers' outcomes and whether the fit used this target.

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        zmp_ref: the target [m].
        lipm: the classic LIPM step's outcome.
        dlipm: the scheduled DLIPM's outcome.
        linear: the single linear correction's outcome.
        fitted_on: whether the fit used this target's LIPM step.
        fit_range_m: range of measured ZMPs the error model was fitted on [m]; None: unknown.
        lipm_pid: the LIPM with a PI on the measured ZMP; None if not run.
        dlipm_fb: the DLIPM with that PI (DLIPM+feedback); None if not run.
    """

    plane: str
    zmp_ref: float
    lipm: ControllerOutcome
    dlipm: ControllerOutcome
    linear: ControllerOutcome
    fitted_on: bool
    fit_range_m: tuple[float, float] | None = None
    lipm_pid: ControllerOutcome | None = None
    dlipm_fb: ControllerOutcome | None = None

    @property
    def extrapolated(self) -> bool:
        """Whether the target lies outside :attr:`fit_range_m` by more than 1 mm.

        (:data:`zmpkit.control.schedule.EXTRAPOLATION_TOLERANCE_M`, the controllers' rule).
        """
        if self.fit_range_m is None:
            return False
        low, high = self.fit_range_m
        tol = EXTRAPOLATION_TOLERANCE_M
        return not low - tol <= self.zmp_ref <= high + tol

    def cells(self) -> dict[str, str]:
        """The row as CSV cells; undefined values are empty cells."""
        lipm, dlipm, linear = self.lipm, self.dlipm, self.linear
        return {
            "plane": self.plane,
            "zmp_ref": _fmt(self.zmp_ref),
            "lipm_zmp": _fmt(lipm.zmp_measured),
            "lipm_error_pct": _fmt(lipm.error_pct),
            "dlipm_zmp": _fmt(dlipm.zmp_measured),
            "dlipm_error_pct": _fmt(dlipm.error_pct),
            "lipm_overshoot_pct": _fmt(lipm.overshoot_pct),
            "dlipm_overshoot_pct": _fmt(dlipm.overshoot_pct),
            "lipm_settling_s": _fmt(lipm.settling_time_s),
            "dlipm_settling_s": _fmt(dlipm.settling_time_s),
            "linear_zmp": _fmt(linear.zmp_measured),
            "linear_error_pct": _fmt(linear.error_pct),
            "linear_overshoot_pct": _fmt(linear.overshoot_pct),
            "linear_settling_s": _fmt(linear.settling_time_s),
            "lipm_rms_oscillation_m": _fmt(lipm.rms_oscillation_m),
            "dlipm_rms_oscillation_m": _fmt(dlipm.rms_oscillation_m),
            "fitted_on": "1" if self.fitted_on else "0",
            **self._status_cells(),
        }

    def outcomes(self) -> dict[str, ControllerOutcome]:
        """The outcomes by controller name (the feedback ones only if they ran)."""
        out = {"lipm": self.lipm, "dlipm": self.dlipm, "linear": self.linear}
        for name in _FEEDBACK_CONTROLLERS:
            outcome: ControllerOutcome | None = getattr(self, name)
            if outcome is not None:
                out[name] = outcome
        return out

    def _status_cells(self) -> dict[str, str]:
        cells = {}
        for name, o in self.outcomes().items():
            if name in _FEEDBACK_CONTROLLERS:
                cells[f"{name}_zmp"] = _fmt(o.zmp_measured)
                cells[f"{name}_error_pct"] = _fmt(o.error_pct)
                cells[f"{name}_overshoot_pct"] = _fmt(o.overshoot_pct)
                cells[f"{name}_settling_s"] = _fmt(o.settling_time_s)
            cells[f"{name}_status"] = o.status
            cells[f"{name}_hold_s"] = _fmt(o.hold_s)
            cells[f"{name}_drift_mm_s"] = _fmt(o.drift_mm_s)
            cells[f"{name}_end_error_pct"] = _fmt(o.end_error_pct)
            cells[f"{name}_error_mm"] = _fmt(o.error_mm)
        cells["extrapolated"] = "1" if self.extrapolated else "0"
        return cells


def _fmt(value: float | None) -> str:
    return "" if value is None else f"{value:.6g}"


def write_table1_csv(rows: Sequence[Table1Row], path: str | Path) -> Path:
    """Write ``rows`` with the columns :data:`TABLE1_COLUMNS` and return the path."""
    path = Path(path)
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=TABLE1_COLUMNS)
        writer.writeheader()
        writer.writerows(row.cells() for row in rows)
    return path


def table1_markdown(rows: Sequence[Table1Row]) -> str:
    """Table 1 as Markdown: ZMP [m], error [%], overshoot [%], settling [s] per controller.

    With feedback runs, the LIPM+PID and DLIPM+feedback errors [%] are two further columns.
    """
    feedback = any(row.dlipm_fb is not None for row in rows)
    extra = " LIPM+PID err [%] | DLIPM+fb err [%] |" if feedback else ""
    head = (
        "| plane | ZMP_ref [m] | LIPM ZMP [m] | LIPM err [%] | DLIPM ZMP [m] | DLIPM err [%] "
        "| linear err [%] | LIPM OS [%] | DLIPM OS [%] | LIPM ts [s] | DLIPM ts [s] |"
        + extra
        + "\n"
        + "|---" * (13 if feedback else 11)
        + "|"
    )
    lines = [head]
    for row in rows:
        c = row.cells()
        more = (
            f" {_pct(c.get('lipm_pid_error_pct', ''))} | {_pct(c.get('dlipm_fb_error_pct', ''))} |"
            if feedback
            else ""
        )
        mark = ("" if row.fitted_on else " *") + (" †" if row.extrapolated else "")
        lines.append(
            f"| {c['plane']} | {c['zmp_ref']}{mark} | {_fixed(c['lipm_zmp'], 5)} "
            f"| {_pct(c['lipm_error_pct'])} "
            f"| {_fixed(c['dlipm_zmp'], 5)} | {_pct(c['dlipm_error_pct'])} "
            f"| {_pct(c['linear_error_pct'])} "
            f"| {_pct(c['lipm_overshoot_pct'])} | {_pct(c['dlipm_overshoot_pct'])} "
            f"| {_fixed(c['lipm_settling_s'], 2)} | {_fixed(c['dlipm_settling_s'], 2)} |" + more
        )
    return (
        "\n".join(lines)
        + "\n\n\\* validation target, not used in the fit. † outside the range the error "
        "model was fitted on: the controllers extrapolate it.\n"
    )


def unsettled_lines(rows: Sequence[Table1Row]) -> list[str]:
    """One line per trial that did not settle: target, controller and why (empty if none)."""
    return [
        f"{row.zmp_ref:g} m, {name.upper()}: {o.unsettled_text()}"
        for row in rows
        for name, o in row.outcomes().items()
        if not o.steady.settled
    ]


def _pct(cell: str) -> str:
    return _fixed(cell, 1)


def _fixed(cell: str, digits: int) -> str:
    return f"{float(cell):.{digits}f}" if cell else "–"
