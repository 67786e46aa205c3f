"""Videos of recorded robot motions: MP4, with a GIF or a keyframe strip where MP4 fails.

A :class:`MotionClip` is one recorded motion (a MuJoCo model, its ``qpos`` per recorded
frame and their times). :func:`write_video` draws one or more clips side by side, after the
simulation, from the recorded configurations (:mod:`zmpkit.analysis.render`): frames are
taken every ``1/fps`` seconds, each showing the last recorded configuration at or before its
time (a clip that ended, e.g. at a fall, keeps its last frame). Each panel carries its label,
the time, and once its robot has fallen a red "fell at 4.32 s (roll)" mark.

The MP4 is H.264, ``yuv420p``, even width and height (what browsers play), written through
``imageio_ffmpeg.write_frames`` (the ffmpeg binary comes in its wheel). A video never ends a
run whose data were written: if ffmpeg cannot write, an animated GIF is written instead, and
if that fails too a keyframe strip (PNG); if no OpenGL context can be created, nothing is
written. Each of these issues a :class:`~zmpkit.errors.VideoWarning`, and the
:class:`VideoResult` says what was written and why.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.analysis.render import (
    WALK_VIEW,
    CameraView,
    OffscreenRenderer,
    RendererUnavailableError,
    error_text,
)
from zmpkit.analysis.video_frames import keyframe_strip, label_panel, write_gif, write_mp4
from zmpkit.errors import ParameterError, VideoWarning

__all__ = ["MotionClip", "VideoResult", "VideoSettings", "write_video"]

VideoKind = Literal["mp4", "gif", "png", "none"]
_TRACK_SMOOTHING_S = 1.0  # the tracking camera follows the base's 1 s moving average [s]


@dataclass(frozen=True, eq=False)
class MotionClip:
    """One recorded motion of a robot.

    Attributes:
        model: the model whose configurations were recorded.
        qpos: configurations (MuJoCo ``qpos``), shape (N, nq).
        time_s: their times [s], shape (N,), increasing.
        label: drawn on the clip's panel, e.g. ``"rigid"``.
        fall_time_s: when the robot fell [s], or None.
        fall_kind: how (``roll``, ``pitch``, ``height``), or None.
    """

    model: mujoco.MjModel
    qpos: NDArray[np.float64]
    time_s: NDArray[np.float64]
    label: str = ""
    fall_time_s: float | None = None
    fall_kind: str | None = None

    def __post_init__(self) -> None:
        qpos = np.asarray(self.qpos, dtype=np.float64)
        time = np.asarray(self.time_s, dtype=np.float64)
        if qpos.ndim != 2 or qpos.shape[1] != self.model.nq or qpos.shape[0] == 0:
            raise ParameterError(
                f"MotionClip.qpos must have shape (N >= 1, nq = {self.model.nq}); got {qpos.shape}"
            )
        if time.shape != (qpos.shape[0],):
            raise ParameterError(
                f"MotionClip.time_s must have shape ({qpos.shape[0]},); got {time.shape}"
            )
        _validate.finite_array("MotionClip.time_s", time)
        if np.any(np.diff(time) <= 0.0):
            raise ParameterError("MotionClip.time_s must be increasing")
        object.__setattr__(self, "qpos", qpos)
        object.__setattr__(self, "time_s", time)

    @property
    def fall_text(self) -> str | None:
        """``"fell at 4.32 s (roll)"``, or None if the robot did not fall."""
        if self.fall_time_s is None:
            return None
        kind = f" ({self.fall_kind})" if self.fall_kind else ""
        return f"fell at {self.fall_time_s:.2f} s{kind}"


@dataclass(frozen=True)
class VideoSettings:
    """How a video is drawn.

    Attributes:
        width_px: width of one clip's panel [px], even.
        height_px: height [px], even.
        fps: frames per second of the video [1/s].
        view: the camera (:data:`~zmpkit.analysis.render.WALK_VIEW` by default).
        window_s: (start, end) of the recorded time shown [s]; None: every clip's whole time.
    """

    width_px: int = 320
    height_px: int = 240
    fps: float = 25.0
    view: CameraView = WALK_VIEW
    window_s: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        for name in ("width_px", "height_px"):
            value = getattr(self, name)
            _validate.in_range(f"VideoSettings.{name}", value, 16, 4096, "px")
            if int(value) != value or int(value) % 2:
                raise ParameterError(f"VideoSettings.{name} must be an even integer; got {value}")
        _validate.in_range("VideoSettings.fps", self.fps, 1.0, 120.0, "1/s")
        if self.window_s is not None and not self.window_s[0] < self.window_s[1]:
            raise ParameterError(
                f"VideoSettings.window_s must be (start, end); got {self.window_s}"
            )


@dataclass(frozen=True)
class VideoResult:
    """What :func:`write_video` wrote.

    Attributes:
        path: the file written, or None if none could be.
        kind: ``"mp4"``, ``"gif"``, ``"png"`` (a keyframe strip) or ``"none"``.
        frames: frames in the file (keyframes for a strip) [-].
        fps: frames per second [1/s] (of the GIF, which may be decimated).
        width_px: frame width [px].
        height_px: frame height [px].
        reason: why the video is not the asked MP4, or None.
    """

    path: Path | None
    kind: VideoKind
    frames: int
    fps: float
    width_px: int
    height_px: int
    reason: str | None = None


def write_video(
    clips: Sequence[MotionClip], path: str | Path, settings: VideoSettings | None = None
) -> VideoResult:
    """Draw ``clips`` side by side and write them as an MP4 at ``path``.

    Falls back to ``path`` with ``.gif``, then to ``<stem>_keyframes.png``, with a
    :class:`~zmpkit.errors.VideoWarning` each time (module docstring).

    Args:
        clips: one panel each, left to right.
        path: the MP4 file to write (its folder is created if missing).
        settings: size of a panel, frame rate, camera; None: :class:`VideoSettings()`.

    Returns:
        What was written, and why it is not the MP4 if it is not.
    """
    if not clips:
        raise ParameterError("write_video needs at least one clip")
    settings = settings or VideoSettings()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    times = _frame_times(clips, settings)
    width, height = settings.width_px * len(clips), settings.height_px
    panels: list[_Panel] = []
    try:
        for clip in clips:
            panels.append(_Panel(clip, settings, times))
    except RendererUnavailableError as exc:
        for panel in panels:
            panel.close()
        return _degraded(None, "none", 0, settings.fps, width, height, str(exc))
    try:
        return _write_with_fallbacks(lambda: _frames(panels, times), path, settings.fps, times.size,
                                     (width, height))  # fmt: skip
    finally:
        for panel in panels:
            panel.close()


def _write_with_fallbacks(
    frames: Callable[[], Iterator[NDArray[np.uint8]]],
    path: Path,
    fps: float,
    count: int,
    size: tuple[int, int],
) -> VideoResult:
    """MP4, else GIF, else a keyframe strip, else nothing; ``frames()`` restarts the frames."""
    width, height = size
    try:
        write_mp4(frames(), path, fps, size)
        return VideoResult(path, "mp4", count, fps, width, height)
    except Exception as exc:  # no ffmpeg, a broken pipe, an encoder error: try a GIF
        reason = f"MP4 not written ({error_text(exc, 120)})"
    path.unlink(missing_ok=True)
    try:
        gif = path.with_suffix(".gif")
        gif_frames, gif_fps = write_gif(frames(), gif, fps)
        return _degraded(gif, "gif", gif_frames, gif_fps, width, height, reason)
    except Exception as exc:  # Pillow cannot write it either: keyframes
        reason += f"; GIF not written ({error_text(exc, 80)})"
    try:
        strip = path.with_name(f"{path.stem}_keyframes.png")
        shown = keyframe_strip(frames(), count, strip)
        return _degraded(strip, "png", shown, fps, width, height, reason)
    except Exception as exc:  # nothing can be written here
        reason += f"; keyframes not written ({error_text(exc, 80)})"
    return _degraded(None, "none", 0, fps, width, height, reason)


def _degraded(
    path: Path | None, kind: VideoKind, frames: int, fps: float, width: int, height: int,
    reason: str,
) -> VideoResult:  # fmt: skip
    written = f"wrote {path.name} instead" if path is not None else "no video written"
    warnings.warn(f"{reason}; {written}", VideoWarning, stacklevel=3)
    return VideoResult(path, kind, frames, fps, width, height, reason)


def _frame_times(clips: Sequence[MotionClip], settings: VideoSettings) -> NDArray[np.float64]:
    """The video's frame times [s], every ``1/fps`` over the clips' time or the window."""
    first = min(float(c.time_s[0]) for c in clips)
    last = max(float(c.time_s[-1]) for c in clips)
    start, end = first, last
    if settings.window_s is not None:
        start, end = max(first, settings.window_s[0]), min(last, settings.window_s[1])
        if end < start:
            raise ParameterError(
                f"VideoSettings.window_s {settings.window_s} lies outside the clips' time "
                f"[{first:g}, {last:g}] s"
            )
    count = math.floor((end - start) * settings.fps + 1e-9) + 1
    return start + np.arange(count) / settings.fps


def _frames(panels: Sequence[_Panel], times: NDArray[np.float64]) -> Iterator[NDArray[np.uint8]]:
    """The video's frames: the panels of each frame time, side by side."""
    for k, t in enumerate(times):
        yield np.concatenate([panel.frame(k, float(t)) for panel in panels], axis=1)


class _Panel:
    """One clip's renderer and camera path over the video's frame times."""

    def __init__(self, clip: MotionClip, settings: VideoSettings, times: NDArray[np.float64]):
        self.clip, self.view = clip, settings.view
        self.rows = np.clip(np.searchsorted(clip.time_s, times, side="right") - 1, 0, None)
        self.renderer = OffscreenRenderer(clip.model, settings.width_px, settings.height_px)
        height = self.renderer.fit_to_robot(clip.qpos[0])
        fovy = math.radians(float(self.renderer.model.vis.global_.fovy))
        self.distance_m = height / self.view.height_fraction / (2.0 * math.tan(fovy / 2.0))
        self.lookat_m = _camera_path(clip, self.rows, times, self.view.track, height)

    def frame(self, k: int, time_s: float) -> NDArray[np.uint8]:
        """Frame ``k`` (at ``time_s`` [s]) of this panel, labelled."""
        image = self.renderer.render(
            self.clip.qpos[self.rows[k]], self.lookat_m[k], self.distance_m, self.view
        )
        clip = self.clip
        fallen = clip.fall_time_s is not None and time_s >= clip.fall_time_s
        return label_panel(image, clip.label, time_s, clip.fall_text if fallen else None)

    def close(self) -> None:
        self.renderer.close()


def _camera_path(
    clip: MotionClip, rows: NDArray[np.intp], times: NDArray[np.float64], track: bool,
    height_m: float,
) -> NDArray[np.float64]:  # fmt: skip
    """Where the camera looks at each frame [m], shape (F, 3): the base, smoothed, or fixed."""
    base = _base_positions(clip)
    lookat = np.repeat(base[:1], rows.size, axis=0) if not track else base[rows]
    if track and rows.size > 1:
        dt = float(np.median(np.diff(times)))
        width = max(1, round(_TRACK_SMOOTHING_S / dt))
        padded = np.pad(lookat, ((width // 2, width - 1 - width // 2), (0, 0)), mode="edge")
        kernel = np.ones(width) / width
        lookat = np.stack([np.convolve(padded[:, i], kernel, "valid") for i in range(3)], 1)
    lookat[:, 2] = 0.5 * height_m
    return lookat


def _base_positions(clip: MotionClip) -> NDArray[np.float64]:
    """The floating base's position per recorded frame [m], shape (N, 3); zeros if fixed."""
    model = clip.model
    if model.njnt and model.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE:
        address = int(model.jnt_qposadr[0])
        return clip.qpos[:, address : address + 3].copy()
    return np.zeros((clip.qpos.shape[0], 3))
