"""The result files of ``zmpkit identify sim``: fit tables and per-experiment fit figures.

:func:`reproduction_checks` replays every experiment with the fitted values and compares
its trunk oscillation and joint angles (:mod:`zmpkit.simfit.validation`), drawing
its per-signal fit figure (:mod:`zmpkit.analysis.simfit_plots`); :func:`write_fit_files`
writes the files of :mod:`zmpkit.simfit.outputs`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit.analysis.simfit_plots import plot_cost_history, plot_signal_fit
from zmpkit.simfit import outputs
from zmpkit.simfit.adequacy import Adequacy
from zmpkit.simfit.experiments import Experiment
from zmpkit.simfit.identifiability import Identifiability
from zmpkit.simfit.noise_intervals import NoiseInterval
from zmpkit.simfit.optimizer import CmaResult
from zmpkit.simfit.problem import FitProblem, simulate
from zmpkit.simfit.validation import ReproductionCheck, reproduction_check

__all__ = ["reproduction_checks", "write_fit_files"]


def reproduction_checks(
    problem: FitProblem, experiments: list[Experiment], values: np.ndarray, out: Path | None
) -> tuple[tuple[ReproductionCheck, ...], dict[str, Path]]:
    """Simulate each experiment with the fitted values; compare; draw its fit figure."""
    held = FitProblem(
        problem.robot,
        problem.sim_effects,
        problem.parameters,
        problem.base_doc,
        tuple(experiments),
        problem.weights,
        problem.sensor_readings,
    )
    checks, files = [], {}
    for i, experiment in enumerate(experiments):
        simulated = simulate(held, values, i)
        checks.append(reproduction_check(experiment.name, experiment.signals, simulated))
        if out is not None:
            label = experiment.name.replace("/", "_")
            files[f"fit_{label}"] = plot_signal_fit(
                experiment.signals, simulated, out / f"fit_{label}.png", experiment.name
            )
    return tuple(checks), files


def write_fit_files(
    problem: FitProblem,
    cma_result: CmaResult,
    judged: Identifiability,
    checks: tuple,
    out: Path,
    figures: bool = True,
    adequacy: Adequacy | None = None,
    intervals: tuple[NoiseInterval, ...] = (),
) -> dict[str, Path]:
    """Write the fit's files into ``out`` and return them by role.

    The files are the fitted truth, parameters (with the model-adequacy check), history,
    identifiability, loose directions and reproduction tables and the cost-history figure.
    """
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
            judged.parameters,
            adequacy,
            intervals,
        ),
        "history": outputs.write_history_csv(out / outputs.HISTORY_CSV, cma_result.history, params),
        "identifiability": outputs.write_identifiability_csv(
            out / outputs.IDENTIFIABILITY_FILE, judged.parameters
        ),
        "sloppy_directions": outputs.write_sloppy_directions_csv(
            out / outputs.SLOPPY_DIRECTIONS_FILE, judged.sloppy
        ),
        "reproduction": outputs.write_reproduction_csv(out / outputs.REPRODUCTION_FILE, *checks),
        "checkpoint": cma_result.checkpoint,
    }
    if figures and cma_result.history:
        files["cost_plot"] = plot_cost_history(
            cma_result.history,
            out / "cost_history.png",
            f"{problem.robot.source} effects {problem.sim_effects}",
        )
    return files
