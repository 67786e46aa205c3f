"""The pipelines' videos: one walk, two walks side by side, one balance step trial.

Each is drawn after the simulation from the configurations the run recorded
(:func:`zmpkit.analysis.video.write_video`), on the model of the simulated robot with the
run's effects. A video never ends a run: where it cannot be written as MP4 a GIF, a keyframe
strip or nothing is written instead, with a :class:`~zmpkit.errors.VideoWarning`.

Size and frame rate: 400 × 300 px per robot at 25 frames/s. With Mesa's software OpenGL (no
GPU) and no multisampling a panel takes about 8 ms of CPU, H.264 encoding as much again;
``zmpkit demo``'s two videos (a 12.6 s walk side by side, 11 s of a balance step trial run
once more) then add about 10 % to its time, within the 20 % allowed.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import mujoco

from zmpkit.analysis.render import BALANCE_VIEW, WALK_VIEW
from zmpkit.analysis.video import MotionClip, VideoResult, VideoSettings, write_video
from zmpkit.errors import VideoWarning, ZmpkitError
from zmpkit.experiments import StepExperimentConfig, run_step_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.pipelines.balance import BalanceResult, step_experiment
from zmpkit.sim.effect_set import EffectSet

__all__ = [
    "BALANCE_VIDEO",
    "SIDE_BY_SIDE_FILE",
    "STEP_TRIAL_AFTER_S",
    "STEP_TRIAL_FILE",
    "WALK_VIDEO",
    "WALK_VIDEO_FILE",
    "effects_label",
    "write_step_trial_video",
    "write_walk_video",
    "write_walks_side_by_side",
]

WALK_VIDEO = VideoSettings(width_px=400, height_px=300, fps=25.0, view=WALK_VIEW)
"""A walk: each robot in a 400 × 300 px panel at 25 frames/s, the camera following it."""
BALANCE_VIDEO = VideoSettings(width_px=400, height_px=300, fps=25.0, view=BALANCE_VIEW)
"""A balance step trial: a fixed camera beside the robot."""
WALK_VIDEO_FILE = "walk.mp4"
SIDE_BY_SIDE_FILE = "walk_side_by_side.mp4"
STEP_TRIAL_FILE = "step_trial.mp4"
STEP_TRIAL_AFTER_S = 10.0
"""A step trial's video shows its recording (from the quiet start-up window before the step)
up to this long after the step [s]."""


def effects_label(effects: str) -> str:
    """``"rigid"`` for no effect, ``"all effects"``, else ``"effects M,I"``."""
    letters = EffectSet.parse(effects).letters
    return {"none": "rigid", "all": "all effects"}.get(letters, f"effects {letters}")


def walk_clip(config: WalkConfig, record: WalkRecord, label: str) -> MotionClip:
    """A walk as a clip: its recorded ``qpos`` on the simulated robot's model with its effects."""
    if record.qpos is None:
        raise ZmpkitError("the walk record has no qpos to draw")
    sim = config.robot.make_simulation(config.effects, config.truth, seed=config.seed)
    return MotionClip(
        sim.model, record.qpos, record.time_s, label, record.fall_time_s, record.fall_kind
    )


def write_walk_video(config: WalkConfig, record: WalkRecord, path: Path) -> VideoResult:
    """Draw one walk into ``path`` (:data:`WALK_VIDEO`); its label names effects and controller."""
    label = f"{effects_label(config.effects)}, {config.controller}"
    return write_video([walk_clip(config, record, label)], path, WALK_VIDEO)


def write_walks_side_by_side(
    walks: Sequence[tuple[WalkConfig, WalkRecord]], path: Path
) -> VideoResult:
    """Draw walks side by side into ``path``, each labelled by its effects (e.g. rigid)."""
    clips = [walk_clip(c, r, effects_label(c.effects)) for c, r in walks]
    return write_video(clips, path, WALK_VIDEO)


def write_step_trial_video(result: BalanceResult, out_dir: Path) -> VideoResult | None:
    """Run the first plane's largest target once more under the scheduled DLIPM; draw it.

    The trial is the one the DLIPM sweep recorded (same seed), now also recording ``qpos``;
    the video (``out_dir/step_trial.mp4``) shows its recording up to
    :data:`STEP_TRIAL_AFTER_S` after the step.

    Returns:
        What was written, or None (with a :class:`~zmpkit.errors.VideoWarning`) if the trial
        could not be run again.
    """
    config = result.config
    plane = config.planes[0]
    target_m = max(config.targets_m, key=abs)
    experiment = step_experiment(config, plane)
    try:
        record = run_step_trial(
            experiment, target_m, result.planes[plane].factories["dlipm"], record_qpos=True
        )
    except ZmpkitError as exc:
        warnings.warn(f"{STEP_TRIAL_FILE} not drawn ({exc})", VideoWarning, stacklevel=2)
        return None
    assert record.qpos is not None  # asked for
    label = f"DLIPM, x_ref = {target_m:g} m, {plane}"
    clip = MotionClip(_model(experiment), record.qpos, record.time, label)
    view = BALANCE_VIEW if plane == "sagittal" else replace(BALANCE_VIEW, azimuth_deg=180.0)
    window = (float(record.time[0]), record.t_step_s + STEP_TRIAL_AFTER_S)
    settings = replace(BALANCE_VIDEO, view=view, window_s=window)
    return write_video([clip], Path(out_dir) / STEP_TRIAL_FILE, settings)


def _model(experiment: StepExperimentConfig) -> mujoco.MjModel:
    robot = experiment.robot
    return robot.make_simulation(experiment.effects, experiment.truth).model
