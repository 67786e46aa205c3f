"""The files of ``zmpkit walk sweep``: figures per controller, ``summary.json``, the report."""

from __future__ import annotations

import json
from pathlib import Path

from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.robustness_plot import plot_push_matrix, plot_robustness
from zmpkit.experiments.robustness import ROBUSTNESS_COLUMNS
from zmpkit.pipelines.walk_sweep import SweepResult
from zmpkit.pipelines.walk_sweep_document import walk_sweep_document

__all__ = ["write_walk_sweep"]


def write_walk_sweep(
    result: SweepResult, out_dir: str | Path, report_format: str = "html"
) -> SweepResult:
    """Write two figures per controller, ``summary.json`` (falls per controller), the report.

    The figures: every case's outcome (:func:`~zmpkit.analysis.robustness_plot.plot_robustness`)
    and the pushes as a matrix of force, direction and phase
    (:func:`~zmpkit.analysis.robustness_plot.plot_push_matrix`).
    """
    out = Path(out_dir)
    files = dict(result.files)
    config = result.config
    for controller in config.controllers:
        rows = [r for r in result.rows if r[0] == controller]
        title = f"{config.robot.title}, effects {config.effects or 'none'}: {controller}" + (
            " with step adjustment" if config.step_adjustment else ""
        )
        files[f"figure_{controller}"] = plot_robustness(
            rows, ROBUSTNESS_COLUMNS, out / f"robustness_{controller}.png", title
        )
        matrix = plot_push_matrix(rows, ROBUSTNESS_COLUMNS, out / f"pushes_{controller}.png", title)
        if matrix is not None:
            files[f"matrix_{controller}"] = matrix
    summary = {
        c: {"falls": f, "cases": n, "step_adjustment": config.step_adjustment}
        for c in config.controllers
        for f, n in [result.falls(c)]
    }
    path = out / "summary.json"
    path.write_text(json.dumps(summary, indent=2) + "\n", encoding="utf-8")
    files["summary"] = path
    written = SweepResult(result.config, result.rows, files, result.started_s)
    files["report"] = write_report(walk_sweep_document(written), out, report_format)
    return SweepResult(result.config, result.rows, files, result.started_s)
