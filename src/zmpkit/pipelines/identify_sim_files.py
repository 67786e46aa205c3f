"""The files of ``zmpkit identify sim``: fit tables, figures, ``recovery.csv`` and the report.

:func:`write_identify_sim` writes the files of :mod:`zmpkit.simfit.outputs`, the per-signal
fit figure of each experiment replayed with the fitted values
(:mod:`zmpkit.analysis.simfit_plots`), the self-test's ``recovery.csv`` and the report.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.simfit_plots import plot_cost_history, plot_signal_fit
from zmpkit.pipelines.identify_sim import IdentifySimResult, Replay
from zmpkit.pipelines.identify_sim_document import identify_sim_document
from zmpkit.simfit import outputs
from zmpkit.simfit.self_test import write_recovery_csv

__all__ = ["write_identify_sim"]


def write_identify_sim(
    result: IdentifySimResult, out_dir: str | Path, report_format: str = "html"
) -> IdentifySimResult:
    """Write the fit's files, figures (as its config asks) and report into ``out_dir``.

    Returns:
        ``result`` with every file written, by role (``"report"``: the report).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = _fit_files(result, out)
    if result.config.figures:
        files |= _replay_figures(result.replays, out)
    if result.recovery:
        files["recovery"] = write_recovery_csv(list(result.recovery), out / "recovery.csv")
    written = replace(result, files=files)
    files["report"] = write_report(identify_sim_document(written), out, report_format)
    return replace(result, files=files)


def _replay_figures(replays: tuple[Replay, ...], out: Path) -> dict[str, Path]:
    """Each replay's recorded against simulated signals, by role ``fit_<experiment>``."""
    files = {}
    for replay in replays:
        name = replay.experiment.name
        label = name.replace("/", "_")
        files[f"fit_{label}"] = plot_signal_fit(
            replay.experiment.signals, replay.simulated, out / f"fit_{label}.png", name
        )
    return files


def _fit_files(result: IdentifySimResult, out: Path) -> dict[str, Path]:
    """Write the fit's files into ``out`` and return them by role.

    The files are the fitted truth, parameters (with the model-adequacy check), history,
    identifiability, loose directions and reproduction tables and the cost-history figure.
    """
    problem, cma_result = result.problem, result.cma
    params, best = problem.parameters, cma_result.best_values
    source = ", ".join(e.name for e in problem.experiments)
    files = {
        "truth": outputs.write_fitted_truth(
            out / outputs.FITTED_TRUTH_FILE, problem.base_doc, params, best, source
        ),
        "parameters": outputs.write_fitted_parameters(
            out / outputs.FITTED_PARAMETERS_FILE,
            problem.robot.source,
            problem.sim_effects,
            cma_result.best_cost,
            params,
            result.identifiability,
            result.adequacy,
            result.intervals,
        ),
        "history": outputs.write_history_csv(out / outputs.HISTORY_CSV, cma_result.history, params),
        "identifiability": outputs.write_identifiability_csv(
            out / outputs.IDENTIFIABILITY_FILE, result.identifiability
        ),
        "intervals": outputs.write_intervals_csv(out / outputs.INTERVALS_FILE, result.intervals),
        "sloppy_directions": outputs.write_sloppy_directions_csv(
            out / outputs.SLOPPY_DIRECTIONS_FILE, result.sloppy_directions
        ),
        "reproduction": outputs.write_reproduction_csv(
            out / outputs.REPRODUCTION_FILE, result.fit_checks, result.held_out_checks
        ),
        "checkpoint": cma_result.checkpoint,
    }
    if result.config.figures and cma_result.history:
        files["cost_plot"] = plot_cost_history(
            cma_result.history,
            out / "cost_history.png",
            f"{problem.robot.source} effects {problem.sim_effects}",
        )
    return files
