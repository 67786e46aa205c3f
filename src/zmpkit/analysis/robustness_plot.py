"""The robustness matrix of one controller: which walks stood, which fell, when and how."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from matplotlib.patches import Rectangle

from zmpkit.analysis.figure import new_figure, save_figure

__all__ = ["case_label", "plot_push_matrix", "plot_robustness"]


def case_label(row: dict[str, str]) -> str:
    """A short name of a case from its CSV cells, e.g. ``push 20 N -y @ 0.25``."""
    if row["push_n"] not in ("", "0"):
        return f"push {row['push_n']} N {row['push_dir']} @ {row['push_phase']}"
    if row["fault"]:
        return f"fault {row['fault']}"
    if row["lateral_mps"] not in ("", "0"):
        return f"lateral {row['lateral_mps']} m/s"
    if row["turn_rad_s"] not in ("", "0"):
        return f"turn {row['turn_rad_s']} rad/s"
    return f"{row['speed_mps']} m/s, {row['step_duration_s']} s steps"


def plot_robustness(
    rows: Sequence[Sequence[str]], columns: Sequence[str], path: str | Path, title: str
) -> Path:
    """One bar per case: how long it walked [s], green if it stood, red (with how) if it fell.

    Args:
        rows: the controller's rows of ``robustness.csv`` (cells as text).
        columns: the CSV's columns.
        path: the PNG to write.
        title: the figure's title.
    """
    cases = [dict(zip(columns, row, strict=True)) for row in rows]
    fig, ax = new_figure(width_in=8.0, height_in=max(3.0, 0.17 * len(cases) + 1.2))
    for i, case in enumerate(cases):
        fell = case["fell"] == "true"
        length = float(case["fall_time_s"]) if fell and case["fall_time_s"] else 1.0
        if fell:
            ax.barh(i, length, color="tab:red")
            ax.text(length, i, f" {case['fall_kind']}", va="center", fontsize=6)
        else:
            ax.text(0.0, i, " stood", va="center", fontsize=6, color="tab:green")
    ax.set_yticks(range(len(cases)), [case_label(c) for c in cases], fontsize=6)
    ax.invert_yaxis()
    ax.set_xlabel("time of the fall [s]")
    falls = sum(c["fell"] == "true" for c in cases)
    ax.set_title(f"{title}: {falls} of {len(cases)} walks fell", fontsize=9)
    return save_figure(fig, path)


def plot_push_matrix(
    rows: Sequence[Sequence[str]], columns: Sequence[str], path: str | Path, title: str
) -> Path | None:
    """The pushes as a matrix: force and direction down, phase of the step across.

    Each cell is one pushed walk: green if it stood, red if it fell (with the kind of fall),
    grey if it was not walked; a cell whose walk moved a step that could not capture the DCM
    carries a ``×``.

    Args:
        rows: the controller's rows of ``robustness.csv`` (cells as text).
        columns: the CSV's columns.
        path: the PNG to write.
        title: the figure's title.

    Returns:
        The PNG, or None when no row is a push.
    """
    cases = [dict(zip(columns, row, strict=True)) for row in rows]
    pushes = [c for c in cases if c["push_n"] not in ("", "0")]
    if not pushes:
        return None
    lines = list(dict.fromkeys((c["push_n"], c["push_dir"]) for c in pushes))
    phases = sorted({c["push_phase"] for c in pushes}, key=float)
    fig, ax = new_figure(width_in=4.0 + 0.6 * len(phases), height_in=1.2 + 0.22 * len(lines))
    for case in pushes:
        i, j = lines.index((case["push_n"], case["push_dir"])), phases.index(case["push_phase"])
        fell = case["fell"] == "true"
        ax.add_patch(_cell(j, i, "tab:red" if fell else "tab:green"))
        uncaptured = case.get("uncaptured_steps", "") not in ("", "0")
        text = (case["fall_kind"] if fell else "") + (" ×" if uncaptured else "")
        ax.text(j, i, text, ha="center", va="center", fontsize=6, color="white")
    ax.set_xlim(-0.5, len(phases) - 0.5)
    ax.set_ylim(len(lines) - 0.5, -0.5)
    ax.set_xticks(range(len(phases)), [f"{float(p):g}" for p in phases], fontsize=7)
    ax.set_yticks(range(len(lines)), [f"{float(f):g} N {d}" for f, d in lines], fontsize=6)
    ax.set_xlabel("phase of the step at which the 0.1 s push starts [-]")
    falls = sum(c["fell"] == "true" for c in pushes)
    ax.set_title(f"{title}: {falls} of {len(pushes)} pushes fell", fontsize=9)
    return save_figure(fig, path)


def _cell(x: float, y: float, color: str) -> Rectangle:
    return Rectangle((x - 0.48, y - 0.45), 0.96, 0.9, color=color)
