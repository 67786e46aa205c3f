"""Videos of walks: one walk, or several side by side, drawn from their records.

Each is drawn after the simulation from the configurations the walk recorded
(:func:`zmpkit.analysis.video.write_video`), on the model of the simulated robot with the
walk's effects. A video never ends a run: where it cannot be written as MP4 a GIF, a keyframe
strip or nothing is written instead, with a :class:`~zmpkit.errors.VideoWarning`.

Size and frame rate: 400 × 300 px per robot at 25 frames/s. With Mesa's software OpenGL (no
GPU) and no multisampling a panel takes about 8 ms of CPU, H.264 encoding as much again;
``zmpkit demo``'s two videos (a 12.6 s walk side by side, 11 s of a balance step trial run
once more) then add about 10 % to its time, within the 20 % allowed.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from zmpkit.analysis.render import WALK_VIEW
from zmpkit.analysis.video import MotionClip, VideoResult, VideoSettings, write_video
from zmpkit.errors import ZmpkitError
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.sim.effect_set import EffectSet

__all__ = [
    "SIDE_BY_SIDE_FILE",
    "WALK_VIDEO",
    "WALK_VIDEO_FILE",
    "effects_label",
    "walk_clip",
    "write_walk_video",
    "write_walks_side_by_side",
]

WALK_VIDEO = VideoSettings(width_px=400, height_px=300, fps=25.0, view=WALK_VIEW)
"""A walk: each robot in a 400 × 300 px panel at 25 frames/s, the camera following it."""
WALK_VIDEO_FILE = "walk.mp4"
SIDE_BY_SIDE_FILE = "walk_side_by_side.mp4"


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
