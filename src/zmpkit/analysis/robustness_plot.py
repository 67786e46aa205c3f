"""The robustness matrix of one controller: which walks stood, which fell, when and how."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from zmpkit.analysis.figure import new_figure, save_figure

__all__ = ["case_label", "plot_robustness"]


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
