"""The files of ``zmpkit sim push``: ``steady_state.csv``, ``steps.png`` and the report.

``steady_state.csv`` has the columns :data:`~zmpkit.experiments.response.STEADY_STATE_COLUMNS`;
``steps.png`` shows the measured against the expected ZMP of every target (paper A Fig. 14).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.zmp_steps_plot import ZmpStepCurve, plot_zmp_steps
from zmpkit.experiments import StepExperimentConfig, write_steady_state_csv
from zmpkit.pipelines.sim_push import SimPushResult
from zmpkit.pipelines.sim_push_document import sim_push_document

__all__ = ["STEADY_STATE_FILE", "STEPS_FIGURE_FILE", "write_sim_push"]

STEADY_STATE_FILE = "steady_state.csv"
STEPS_FIGURE_FILE = "steps.png"
_AXIS_LABEL = {"sagittal": "ZMP x (forward)", "frontal": "ZMP y (left)"}


def write_sim_push(
    result: SimPushResult, out_dir: str | Path, report_format: str = "html"
) -> SimPushResult:
    """Write ``steady_state.csv``, ``steps.png`` and the report into ``out_dir``.

    Returns:
        ``result`` with the files written, by role (``steady_state``, ``figure``, ``report``).
    """
    out = Path(out_dir)
    config = result.config
    files = {"steady_state": write_steady_state_csv(result.responses, out / STEADY_STATE_FILE)}
    curves = [
        ZmpStepCurve(f"{1000 * r.zmp_ref:g} mm", r.time_since_step, r.zmp_measured, r.zmp_expected)
        for r in result.responses
    ]
    files["figure"] = plot_zmp_steps(
        curves, out / STEPS_FIGURE_FILE, title=_title(config), axis_label=_AXIS_LABEL[config.plane]
    )
    written = replace(result, files=files)
    files["report"] = write_report(sim_push_document(written), out, report_format)
    return replace(result, files=files)


def _title(config: StepExperimentConfig) -> str:
    push = ""
    if config.push is not None:
        push = f", push {config.push.force_n:g} N for {config.push.duration_s:g} s"
    return (
        f"{config.robot.title} {config.plane} ZMP steps, effects {config.effects}, "
        f"seed {config.seed}{push}"
    )
