"""Recorded experiments the simulator is fitted to, and how their folders are read.

Only signals a real robot records enter the fit (:class:`RecordedSignals`): the commanded
joint angles, the joint encoders, the ZMP from the ankle F-T sensors and the trunk tilt
from the IMU. Every experiment names its robot. Two kinds of experiment:

- :class:`WalkExperiment` — a walk folder written by ``zmpkit walk``
  (:mod:`zmpkit.experiments.walk_dataset`): ``summary.json`` and ``timeseries.csv``. The
  CSV holds the commanded angles of the six pitch joints only; the whole commanded
  trajectory is re-planned from the walk's command (speed, step duration, duration, CoM
  height), which a user knows because they commanded it (:mod:`~zmpkit.simfit.walk_plan`).
  A walk played open loop is checked against its recorded commanded angles and replayed
  from the plan; a walk with one of zmpkit's feedback controllers (the default ``zmpip``,
  ``dcm``) is checked against its recorded plan (ZMP reference and CoM) and re-simulated
  with its controller in closed loop (:mod:`~zmpkit.simfit.closed_loop`). A walk that fell
  is kept up to shortly before the fall (:data:`~zmpkit.simfit.walk_plan.FALL_MARGIN_S`).
- :class:`StepExperiment` — one trial of a step dataset
  (:func:`~zmpkit.experiments.read_step_dataset`): the commanded setpoints of every joint are
  in the trial CSV; the robot stands ``settle_s`` before the recording starts.
- :class:`~zmpkit.simfit.shooting_window.ShootingWindow` — a window of a walk log of a
  controller zmpkit does not have (:mod:`zmpkit.experiments.walk_log`: a ``.csv`` or
  ``.parquet`` file, or a folder holding ``walk_log.csv`` and no ``summary.json``): the log
  is fitted by multiple shooting, each window replayed open loop from its measured state
  (:mod:`~zmpkit.simfit.shooting_window`); every window is one experiment.

:func:`read_experiments` reads a list of folders; every problem is an
:class:`~zmpkit.errors.InputFileError` naming the file and what was expected.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import astuple, dataclass, replace
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError, ZmpkitError
from zmpkit.experiments import read_step_dataset
from zmpkit.experiments.dataset import META_FILE
from zmpkit.experiments.walk_dataset import PITCH_JOINTS, SERIES_FILE, SUMMARY_FILE, read_series
from zmpkit.robots.robot import Robot
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N, zmp_series
from zmpkit.sensors.imu import tilt_from_quaternions
from zmpkit.sim.effect_set import EffectSet
from zmpkit.simfit.closed_loop import WalkSettings
from zmpkit.simfit.log_experiment import read_log_windows, walk_log_path
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.shooting_window import DEFAULT_BURN_IN_S, DEFAULT_WINDOW_S, ShootingWindow
from zmpkit.simfit.walk_plan import match_closed_loop_plan, match_walk_plan
from zmpkit.walking.walk_controllers import CONTROLLERS

__all__ = [
    "Experiment",
    "ShootingWindow",
    "StepExperiment",
    "WalkExperiment",
    "read_experiments",
    "read_walk_folder",
    "simulated_effects",
]


@dataclass(frozen=True, eq=False)
class WalkExperiment:
    """A walk: its command and its recorded signals.

    Attributes:
        name: label (the folder name).
        speed_mps: commanded forward speed [m/s].
        step_duration_s: step duration [s].
        duration_s: walking time of the pattern [s].
        com_height_m: CoM height of the pattern [m].
        signals: the recording (a fallen walk's up to shortly before the fall).
        robot: the robot that walked.
        closed_loop: what the walk ran when a feedback controller walked it (re-simulated
            in closed loop); None for a walk played open loop.
        fall_time_s: when the recorded walk fell [s], or None.
        effects: the effects the walk ran with (``summary.json``), or None if unknown.
    """

    name: str
    speed_mps: float
    step_duration_s: float
    duration_s: float
    com_height_m: float
    signals: RecordedSignals
    robot: Robot
    closed_loop: WalkSettings | None = None
    fall_time_s: float | None = None
    effects: str | None = None


@dataclass(frozen=True, eq=False)
class StepExperiment:
    """A step trial: commanded setpoints and recorded signals.

    Attributes:
        name: label (dataset folder and trial file).
        plane: ``"sagittal"`` or ``"frontal"``.
        settle_s: standing time before the recording starts [s].
        mounts: the F-T sensor mounts, ``{"right": ..., "left": ...}``.
        signals: the recording; ``q_cmd_rad`` holds every driven joint.
        robot: the robot that stepped.
        contact_threshold_n: the dataset's contact threshold, recorded and simulated ZMP
            alike [N].
    """

    name: str
    plane: str
    settle_s: float
    mounts: dict
    signals: RecordedSignals
    robot: Robot
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N


Experiment = WalkExperiment | StepExperiment | ShootingWindow
"""Any experiment the fit takes."""


def _read_summary(folder: Path) -> dict:
    path = folder / SUMMARY_FILE
    try:
        summary = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as exc:
        raise InputFileError(path, f"cannot read the walk summary: {exc}") from None
    for key in ("fell", "commanded_speed_mps", "step_frequency_hz"):
        if key not in summary:
            raise InputFileError(path, f"missing field '{key}' of a zmpkit walk summary")
    controller = summary.get("controller", "open")
    if controller not in CONTROLLERS:
        raise InputFileError(
            path,
            f"controller {controller!r} is not one of zmpkit's ({', '.join(CONTROLLERS)})",
            column="controller",
        )
    return summary


def _walk_settings(
    summary: dict, robot: Robot, speed: float, step_s: float, effects: str
) -> WalkSettings:
    """What a walk with feedback ran, from its summary (``duration_s`` found later)."""
    height = robot.require_walking().com_height_m
    return WalkSettings(
        robot,
        speed,
        step_s,
        0.0,
        height,
        controller=str(summary["controller"]),
        effects=effects,
        seed=int(summary.get("seed", 0)),
        lateral_speed_mps=float(summary.get("commanded_lateral_speed_mps", 0.0)),
        turn_rate_rps=float(summary.get("commanded_turn_rate_rps", 0.0)),
        pushes=tuple(str(p) for p in summary.get("pushes", ())),
        step_adjustment=int(summary.get("adjusted_steps", 0)) > 0,
    )


_REFERENCE_COLUMNS = ("zmp_ref_x_m", "zmp_ref_y_m", "com_ref_x_m", "com_ref_y_m")


def _walk_signals(
    path: Path, header: list[str], table: NDArray[np.float64], joints: tuple[str, ...]
) -> RecordedSignals:

    col = {name: table[:, header.index(name)] for name in header}
    time = col["time_s"]
    if time.size < 16 or np.any(np.diff(time) <= 0):
        raise InputFileError(
            path, "time_s must rise strictly over at least 16 rows", column="time_s"
        )
    for name in ("time_s", "trunk_pitch_rad", *(f"{j}_meas_rad" for j in joints)):
        if not np.all(np.isfinite(col[name])):
            raise InputFileError(path, "expected finite numbers", column=name)
    return RecordedSignals(
        time_s=time,
        joint_names=joints,
        q_cmd_rad=np.column_stack([col[f"{j}_cmd_rad"] for j in joints]),
        q_meas_rad=np.column_stack([col[f"{j}_meas_rad"] for j in joints]),
        zmp_m=np.column_stack([col["zmp_x_m"], col["zmp_y_m"]]),
        trunk_tilt_rad=col["trunk_pitch_rad"],
        force_z_n=np.column_stack([col["right_fz_n"], col["left_fz_n"]]),
    )


def read_walk_folder(folder: str | Path, robot: Robot) -> WalkExperiment:
    """Read a ``zmpkit walk`` output folder of ``robot`` as a :class:`WalkExperiment`.

    Raises:
        InputFileError: on a missing or malformed file, an unknown controller, a recording
            the re-planned walk does not reproduce, or a walk that fell too soon to fit.
    """
    folder = Path(folder)
    summary = _read_summary(folder)
    path = folder / SERIES_FILE
    joints = robot.require_walking().series_joints or PITCH_JOINTS
    header, table = read_series(path, joints)
    signals = _walk_signals(path, header, table, tuple(joints))
    speed = float(summary["commanded_speed_mps"])
    step_s = 1.0 / float(summary["step_frequency_hz"])
    fell = bool(summary["fell"])
    effects = _recorded_effects(folder / SUMMARY_FILE, summary)
    settings = None
    if summary.get("controller", "open") == "open":
        match = match_walk_plan(robot, path, speed, step_s, signals, fell, effects or "all")
    else:
        settings = _walk_settings(summary, robot, speed, step_s, effects or "all")
        references = table[:, [header.index(c) for c in _REFERENCE_COLUMNS]]
        try:
            match = match_closed_loop_plan(path, settings, signals.time_s, references, fell)
        except ParameterError as exc:  # a summary no zmpkit walk writes
            raise InputFileError(folder / SUMMARY_FILE, str(exc)) from None
        settings = replace(settings, duration_s=match.duration_s)
    recorded_fall = summary.get("fall_time_s")
    fall_s = float(recorded_fall) if isinstance(recorded_fall, int | float) else None
    if fell and fall_s is None:
        fall_s = float(signals.time_s[-1])
    return WalkExperiment(
        folder.name,
        speed,
        step_s,
        match.duration_s,
        match.com_height_m,
        signals.head(match.rows),
        robot,
        settings,
        fall_s,
        effects,
    )


def _recorded_effects(path: Path, summary: dict) -> str | None:
    if "effects" not in summary:
        return None
    try:
        return EffectSet.parse(str(summary["effects"])).letters
    except ParameterError as exc:
        raise InputFileError(path, str(exc), column="effects") from None


def simulated_effects(fitted: str, experiments: Sequence[Experiment]) -> str:
    """The effects the fit simulates: ``fitted`` and every effect a recorded walk ran with.

    A walk folder says which effects its robot ran (``summary.json``); a candidate runs them
    too, the unfitted ones at the base truth's values: a simulator without them would
    explain their footprint by moving the fitted parameters.

    Args:
        fitted: the fit's effect letters, e.g. ``"M,G,S"``.
        experiments: the recorded experiments.
    """
    on = EffectSet.parse(fitted)
    for x in experiments:
        if isinstance(x, WalkExperiment) and x.effects is not None:
            ran = EffectSet.parse(x.effects)
            on = EffectSet(*(a or b for a, b in zip(astuple(on), astuple(ran), strict=True)))
    return on.letters


def _step_experiments(folder: Path, robot: Robot) -> list[StepExperiment]:

    dataset = read_step_dataset(folder)
    settings = dataset.meta.get("settings", {})
    if settings.get("push") is not None:
        raise InputFileError(
            folder / "meta.json",
            "trials with a push cannot be replayed; fit to ZMP-step trials without push",
            column="settings",
        )
    out = []
    for trial in dataset.trials:
        loads = zmp_series(
            trial.time,
            trial.right_wrench,
            trial.left_wrench,
            dataset.mounts["right"],
            dataset.mounts["left"],
            contact_threshold_n=dataset.contact_threshold_n,
        )
        signals = RecordedSignals(
            trial.time,
            trial.joint_names,
            trial.commanded,
            trial.encoders,
            loads.zmp,
            tilt_from_quaternions(trial.imu[:, 6:10], trial.plane),
            np.stack([loads.fz_right, loads.fz_left], axis=1),
        )
        name = f"{folder.name}/{trial.plane}_{trial.target_m:g}"
        settle = float(settings.get("settle_s", trial.time[0]))
        mounts = dict(dataset.mounts)
        threshold = dataset.contact_threshold_n
        out.append(StepExperiment(name, trial.plane, settle, mounts, signals, robot, threshold))
    return out


def read_experiments(
    folders: Sequence[str | Path],
    robot: Robot,
    window_s: float = DEFAULT_WINDOW_S,
    burn_in_s: float = DEFAULT_BURN_IN_S,
) -> list[Experiment]:
    """Read recorded experiment folders of ``robot``; each experiment names it.

    The robot's fit says what it replays (:attr:`~zmpkit.robots.robot.FitSpec.experiment`):
    walks — a walk output folder (``summary.json`` + ``timeseries.csv``) — or steps — a step
    dataset (``meta.json`` + trial CSVs), each trial one experiment. A robot that replays
    walks takes step datasets too (a designed double-support experiment,
    :mod:`zmpkit.experiments.double_support`, is one): a folder with ``meta.json`` is read as
    one. A walk log (a ``.csv`` or ``.parquet`` file, or a folder with ``walk_log.csv`` and
    no ``summary.json``; on a robot that replays steps, a ``zmpkit walk`` folder's
    ``walk_log.csv`` too) is cut into windows of ``window_s`` [s] with an unscored
    ``burn_in_s`` [s], each one experiment.

    Raises:
        InputFileError: naming the folder or file and what was expected.
    """
    if not folders:
        raise InputFileError("DATA", "no experiment folders given; expected at least one")
    kind = robot.require_fit().experiment
    out: list[Experiment] = []
    for item in folders:
        folder = Path(item)
        log = walk_log_path(folder, walk_folders=kind != "walk")
        if log is not None:
            out.extend(read_log_windows(log, robot, window_s, burn_in_s))
            continue
        if not folder.is_dir():
            raise InputFileError(folder, "expected an experiment folder (does not exist)")
        if kind == "walk" and not (folder / META_FILE).is_file():
            out.append(read_walk_folder(folder, robot))
            continue
        try:
            out.extend(_step_experiments(folder, robot))
        except InputFileError:
            raise
        except ZmpkitError as exc:
            raise InputFileError(folder, f"not a step dataset: {exc}") from None
    return out
