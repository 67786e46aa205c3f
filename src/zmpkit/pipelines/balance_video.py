"""The video of ``zmpkit balance``: one step trial under the scheduled DLIPM, run once more.

Drawn after the sweeps (:func:`zmpkit.analysis.video.write_video`) on the model of the
simulated robot with the run's effects; walks are drawn by :mod:`zmpkit.analysis.walk_video`.
A video never ends a run: where it cannot be written as MP4 a GIF, a keyframe strip or
nothing is written instead, with a :class:`~zmpkit.errors.VideoWarning`.
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from pathlib import Path

import mujoco

from zmpkit.analysis.render import BALANCE_VIEW
from zmpkit.analysis.video import MotionClip, VideoResult, VideoSettings, write_video
from zmpkit.errors import VideoWarning, ZmpkitError
from zmpkit.experiments import StepExperimentConfig, run_step_trial
from zmpkit.pipelines.balance import BalanceResult, step_experiment

__all__ = ["BALANCE_VIDEO", "STEP_TRIAL_AFTER_S", "STEP_TRIAL_FILE", "write_step_trial_video"]

BALANCE_VIDEO = VideoSettings(width_px=400, height_px=300, fps=25.0, view=BALANCE_VIEW)
"""A balance step trial: a fixed camera beside the robot, 400 × 300 px at 25 frames/s."""
STEP_TRIAL_FILE = "step_trial.mp4"
STEP_TRIAL_AFTER_S = 10.0
"""A step trial's video shows its recording (from the quiet start-up window before the step)
up to this long after the step [s]."""


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
