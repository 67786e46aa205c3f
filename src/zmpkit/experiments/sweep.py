"""Run a step / push sweep into a dataset folder, resumably, on a small process pool.

Each trial's CSV is written (atomically) as soon as it finishes and ``meta.json`` is rewritten
to list it, so an interrupted sweep loses no finished trial. Run again with the same folder
and settings, it skips every trial whose file is listed in ``meta.json`` and reads back; a
folder holding a sweep with other settings is refused rather than mixed.
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from typing import Any

from zmpkit import __version__
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.config import StepExperimentConfig, trial_file_name
from zmpkit.experiments.dataset import (
    DATASET_FORMAT,
    META_FILE,
    StepDataset,
    column_units,
    read_meta,
    read_step_dataset,
    read_trial_csv,
    write_meta,
    write_trial_csv,
)
from zmpkit.experiments.lean import (
    design_lean_model,
    design_support_interval,
    lean_angle,
    lean_angle_joints,
)
from zmpkit.experiments.trial import LeanController, run_step_trial
from zmpkit.experiments.trial_record import StepTrialRecord

__all__ = [
    "DEFAULT_WORKERS",
    "MAX_WORKERS",
    "ProgressCallback",
    "check_sweep",
    "new_meta",
    "run_step_sweep",
]

DEFAULT_WORKERS = 2
"""Processes that run trials in parallel by default."""
MAX_WORKERS = 256
"""Most parallel processes or threads a run may ask for."""
_CONSISTENT_FIELDS: tuple[str, ...]
_CONSISTENT_FIELDS = ("format", "robot", "plane", "effects", "seed", "settings", "joint_names")
_CONSISTENT_FIELDS += ("sensor_mounts", "lean_length_m", "controller")

ProgressCallback = Callable[[int, int, float], None]
"""``progress(finished, total, target_m)``: called once per trial, skipped ones included."""


def new_meta(
    config: StepExperimentConfig, controller: Callable[[], LeanController] | None = None
) -> dict[str, Any]:
    """``meta.json`` of a sweep of ``config`` with no trials yet.

    ``controller`` (the lean controller's factory, if any) is recorded by its ``settings()``
    when it has one, else by its repr, under the key ``"controller"`` (None: LIPM step).
    """
    robot = config.robot
    joints = tuple(robot.driven_joints)
    return {
        "format": DATASET_FORMAT,
        "robot": robot.source,
        "plane": config.plane,
        "effects": config.effects,
        "seed": config.seed,
        "settings": config.settings(),
        "joint_names": list(joints),
        "sensor_mounts": robot.feet_mounts(),
        "contact_threshold_n": robot.contact_force_threshold_n,
        "units": column_units(joints),
        "zmpkit_version": __version__,
        "lean_length_m": design_lean_model(config.robot, config.plane).lean_length_m,
        "lean_length_source": "design model: rigid MJCF (effects none), CAD masses and geometry",
        "lean_angle_joints": lean_angle_joints(config.robot, config.plane),
        "controller": _controller_settings(controller),
        "trials": [],
    }


def _controller_settings(controller: Callable[[], LeanController] | None) -> Any:
    if controller is None:
        return None
    settings = getattr(controller, "settings", None)
    return _json_roundtrip(settings()) if callable(settings) else repr(controller)


def _trial_entry(config: StepExperimentConfig, record: StepTrialRecord) -> dict[str, Any]:
    return {
        "file": trial_file_name(record.plane, record.target_m),
        "target_m": record.target_m,
        "t_step_s": record.t_step_s,
        "lean_angle_rad": record.lean_angle_rad,
        "startup_window_s": [record.t_step_s - config.startup_window_s, record.t_step_s],
        "hold_end": record.hold_end,
        "hold_note": record.hold_note,
        "hold_s": float(record.time[-1] - record.t_step_s),
    }


def _json_roundtrip(value: Any) -> Any:
    import json

    return json.loads(json.dumps(value))


def _resume(folder: Path, meta: dict[str, Any]) -> list[dict[str, Any]]:
    """Finished trials of an earlier run in ``folder``; raises if its settings differ."""
    if not (folder / META_FILE).exists():
        return []
    old = read_meta(folder)
    fresh = _json_roundtrip(meta)
    for key in _CONSISTENT_FIELDS:
        if old.get(key) != fresh[key]:
            raise ParameterError(
                f"{folder / META_FILE} holds a sweep with another {key!r} "
                f"({old.get(key)!r}, this run: {fresh[key]!r}); use another output folder"
            )
    done = []
    for k, entry in enumerate(old["trials"]):
        try:
            read_trial_csv(folder / entry["file"], old, k)
        except InputFileError:
            continue
        done.append(entry)
    return done


def check_sweep(config: StepExperimentConfig) -> None:
    """Fail before any work on a target out of reach or an unreadable truth file.

    A target is in reach when it lies strictly inside the design model's support polygon
    along the plane's axis (:func:`~zmpkit.experiments.lean.design_support_interval`) and a
    lean reaches it.

    Raises:
        ParameterError: naming the first target out of reach and the reachable range.
        InputFileError: on an unreadable truth file.
    """
    robot, plane = config.robot, config.plane
    length = design_lean_model(robot, plane).lean_length_m
    low, high = design_support_interval(robot, plane)
    for target in config.targets_m:
        if not low < target < high:
            raise ParameterError(
                f"ZMP target {target:g} m lies outside {robot.source}'s support polygon in the "
                f"{plane} plane; reachable targets lie in ({low:g}, {high:g}) m"
            )
        lean_angle(target, length)
    robot.description(config.effects, config.truth)


def _pool(workers: int) -> ProcessPoolExecutor:
    return ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"))


def _finish(
    folder: Path, meta: dict[str, Any], config: StepExperimentConfig, record: StepTrialRecord
) -> None:
    entry = _trial_entry(config, record)
    write_trial_csv(record, folder / entry["file"])
    trials = [e for e in meta["trials"] if e["file"] != entry["file"]] + [entry]
    meta["trials"] = sorted(trials, key=lambda e: e["target_m"])
    write_meta(meta, folder)


def run_step_sweep(
    config: StepExperimentConfig,
    out_dir: str | Path,
    *,
    workers: int = DEFAULT_WORKERS,
    progress: ProgressCallback | None = None,
    controller: Callable[[], LeanController] | None = None,
) -> StepDataset:
    """Run every trial of ``config`` not yet in ``out_dir`` and return the whole dataset.

    Args:
        config: the sweep.
        out_dir: the dataset folder, created if missing; resumed if it holds the same sweep.
        workers: processes running trials in parallel (1: in this process).
        progress: called after each trial (and once per skipped one).
        controller: a picklable factory of the lean controller driving every trial (see
            :func:`~zmpkit.experiments.trial.run_step_trial`); None: the LIPM step.

    Raises:
        ParameterError: on ``workers < 1``, or if ``out_dir`` holds a sweep of other settings.
    """
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    check_sweep(config)
    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    meta = new_meta(config, controller)
    meta["trials"] = _resume(folder, meta)
    write_meta(meta, folder)
    done = {e["file"] for e in meta["trials"]}
    todo = [t for t in config.targets_m if trial_file_name(config.plane, t) not in done]
    total, finished = len(config.targets_m), 0
    for target in [t for t in config.targets_m if t not in todo]:
        finished += 1
        if progress is not None:
            progress(finished, total, target)
    for record in _records(config, todo, workers, controller):
        _finish(folder, meta, config, record)
        finished += 1
        if progress is not None:
            progress(finished, total, record.target_m)
    return read_step_dataset(folder)


def _records(
    config: StepExperimentConfig,
    targets: list[float],
    workers: int,
    controller: Callable[[], LeanController] | None,
) -> Iterator[StepTrialRecord]:
    """Yield the trial records of ``targets`` as they finish."""
    if workers == 1 or len(targets) <= 1:
        for target in targets:
            yield run_step_trial(config, target, controller)
        return
    with _pool(min(workers, len(targets))) as pool:
        futures = [pool.submit(run_step_trial, config, t, controller) for t in targets]
        for future in as_completed(futures):
            yield future.result()
