r"""Replicas of walk logs recorded through the pipeline the data went through.

A fitted walk log's error has two parts: the sensors' noise, and the **estimator's bias** —
what the multiple shooting itself does to any robot's data: each window starts from a
*measured* state (encoders, a differentiated speed, the IMU, the stance sole) with the
unmeasured ones — gear deflection, the winding current — at zero
(:mod:`~zmpkit.simfit.shooting_window`), while the robot that walked had them developed
and its commands answered them. The bias does not average out: the fit of a robot whose
truth is known moves the gear stiffness by several percent whatever the noise seed.

A replica that is to reproduce both must be the data's whole pipeline run again on a
robot that *is* the fitted model:

1. the fitted truth (the base truth's sensor specification: noise, quantisation, filter)
   walks the recorded walk again — the same command, the same controller in closed loop
   (:func:`~zmpkit.simfit.closed_loop.simulate_closed_loop`, as ``zmpkit walk`` ran it,
   read from the walk folder beside the log), with the noise seed
   :data:`~zmpkit.simfit.adequacy.REPLICA_SEED` + k;
2. its sensor log (:func:`~zmpkit.experiments.walk_log.walk_log_from_record`) is cut into
   windows exactly as the data's log was (:func:`~zmpkit.simfit.shooting_window.log_windows`,
   the same window and burn-in), each with its own measured start state.

Re-fitting replica ``k`` (:mod:`~zmpkit.simfit.replica_refit`) then gives an estimate that
carries the noise *and* the bias of the pipeline (:mod:`~zmpkit.simfit.refit_intervals`).

Only a log written by ``zmpkit walk`` with one of its feedback controllers says how to
walk it again (``summary.json`` beside the log); for any other log :func:`walk_settings`
answers None and the fit falls back to the noise-only intervals
(:mod:`~zmpkit.simfit.noise_intervals`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, SimulationDivergedError
from zmpkit.experiments.walk_dataset import SUMMARY_FILE
from zmpkit.experiments.walk_log import walk_log_from_record
from zmpkit.simfit.adequacy import REPLICA_SEED
from zmpkit.simfit.closed_loop import WalkSettings, simulate_closed_loop
from zmpkit.simfit.experiments import read_walk_folder
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.shooting_window import ShootingWindow, log_windows
from zmpkit.simfit.truth_doc import RobotTruth, load_robot_truth, truth_doc_with

__all__ = ["pipeline_replica", "walk_settings"]


def _windows(problem: FitProblem) -> list[ShootingWindow]:
    return [e for e in problem.experiments if isinstance(e, ShootingWindow)]


def walk_settings(problem: FitProblem) -> dict[str, WalkSettings] | None:
    """How each fitted log was walked, by its file.

    None unless every experiment is a window of a log that ``zmpkit walk`` wrote with a
    feedback controller (module docstring).
    """
    windows = _windows(problem)
    if not windows or len(windows) != len(problem.experiments):
        return None
    out: dict[str, WalkSettings] = {}
    for source in dict.fromkeys(w.source for w in windows):
        folder = Path(source).parent
        if not source or not (folder / SUMMARY_FILE).exists():
            return None
        try:
            settings = read_walk_folder(folder, problem.robot).closed_loop
        except InputFileError:
            return None
        if settings is None:
            return None
        out[source] = settings
    return out


def _walk_again(
    window: ShootingWindow, settings: WalkSettings, truth: RobotTruth, seed: int
) -> list[ShootingWindow]:
    """The log's walk by ``truth`` with noise ``seed``, cut as ``window``'s log was."""
    again = replace(settings, seed=seed)
    sim = window.robot.make_simulation(again.effects, truth, seed=seed)
    log = walk_log_from_record(simulate_closed_loop(again, sim))
    return log_windows(log, window.robot, window.log_name, window.window_s, window.burn_in_s)


def pipeline_replica(
    problem: FitProblem,
    values: NDArray[np.float64] | Sequence[float],
    k: int,
    settings: dict[str, WalkSettings],
) -> FitProblem | None:
    """Replica ``k`` of ``problem``'s logs recorded by the model at ``values`` [units].

    Returns:
        The same fit problem on the replica's windows (module docstring), or None when a
        replica walk diverged or left no window.
    """
    vals = np.asarray(values, dtype=float).tolist()
    truth = load_robot_truth(
        problem.robot, truth_doc_with(problem.base_doc, problem.parameters, vals)
    )
    first = {w.source: w for w in reversed(_windows(problem))}
    windows: list[ShootingWindow] = []
    try:
        for source, walk in settings.items():
            windows += _walk_again(first[source], walk, truth, REPLICA_SEED + k)
    except (InputFileError, SimulationDivergedError):
        return None
    return replace(problem, experiments=tuple(windows))
