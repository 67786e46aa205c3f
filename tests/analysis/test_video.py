"""Videos of recorded motions: MP4 read back, side by side, fall marks, and every fallback."""

from __future__ import annotations

import os
from pathlib import Path

import imageio_ffmpeg
import mujoco
import numpy as np
import pytest
from PIL import Image

from helpers.gl import skip_without_gl
from zmpkit.analysis import render, video
from zmpkit.analysis.render import CameraView
from zmpkit.analysis.video import MotionClip, VideoSettings, write_video
from zmpkit.analysis.video_frames import KEYFRAMES, label_panel
from zmpkit.errors import ParameterError, VideoWarning

SCENE = """
<mujoco>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1"/>
    <geom type="plane" size="5 5 0.1" rgba="0.8 0.8 0.8 1"/>
    <body name="block" pos="0 0 0.2">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.2" rgba="0.9 0.2 0.1 1"/>
    </body>
  </worldbody>
</mujoco>
"""
FIXED = CameraView(azimuth_deg=90.0, elevation_deg=-10.0, height_fraction=0.3, track=False)
SMALL = VideoSettings(width_px=96, height_px=64, fps=10.0, view=FIXED)


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(SCENE)


@pytest.fixture(scope="module")
def gl() -> None:
    """Skip where no offscreen OpenGL context can be created (no EGL library, no display)."""
    skip_without_gl()


def sliding_block(model: mujoco.MjModel, label: str = "", **fall: object) -> MotionClip:
    """The block slides 0.6 m along +x in 2 s, recorded every 10 ms."""
    time = np.arange(201) * 0.01
    qpos = np.tile(model.qpos0, (time.size, 1))
    qpos[:, 0] = 0.3 * time
    return MotionClip(model, qpos, time, label, **fall)  # type: ignore[arg-type]


def read_mp4(path: Path) -> tuple[dict, list[np.ndarray]]:
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    width, height = meta["size"]
    return meta, [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]


@pytest.mark.slow
def test_a_motion_is_written_as_an_mp4_a_browser_plays(model, gl, tmp_path: Path) -> None:
    result = write_video([sliding_block(model, "block")], tmp_path / "block.mp4", SMALL)
    meta, frames = read_mp4(tmp_path / "block.mp4")
    assert (result.kind, result.reason, result.path) == ("mp4", None, tmp_path / "block.mp4")
    assert result.frames == len(frames) == 21  # 2 s at 10 frames/s, both ends included
    assert meta["size"] == (96, 64) == (result.width_px, result.height_px)
    assert meta["codec"] == "h264"
    assert meta["pix_fmt"].startswith("yuv420p")
    assert all(f.std() > 10.0 for f in frames)  # not blank
    moved = np.abs(frames[-1].astype(int) - frames[0].astype(int)).mean()
    assert moved > 2.0  # the block crossed the fixed camera's image


def test_a_tracking_camera_keeps_the_robot_in_the_middle(model, gl) -> None:
    clip = sliding_block(model)
    times = np.array([0.0, 2.0])
    panel = video._Panel(clip, VideoSettings(width_px=96, height_px=64, view=FIXED), times)
    tracked = video._Panel(clip, VideoSettings(width_px=96, height_px=64), times)
    try:
        assert panel.lookat_m[1, 0] == panel.lookat_m[0, 0]
        assert tracked.lookat_m[1, 0] - tracked.lookat_m[0, 0] == pytest.approx(0.6, abs=0.1)
    finally:
        panel.close()
        tracked.close()


def test_clips_side_by_side_are_labelled_and_a_fall_is_marked(model, gl, tmp_path: Path) -> None:
    clips = [sliding_block(model, "rigid"),
             sliding_block(model, "all effects", fall_time_s=1.0, fall_kind="roll")]  # fmt: skip
    result = write_video(clips, tmp_path / "both.mp4", SMALL)
    meta, frames = read_mp4(tmp_path / "both.mp4")
    assert meta["size"] == (192, 64) == (result.width_px, result.height_px)

    def red_top_right(frame: np.ndarray) -> int:
        corner = frame[:14, -40:].astype(int)
        return int(np.count_nonzero((corner[..., 0] > 150) & (corner[..., 1] < 90)))

    assert red_top_right(frames[5]) == 0  # 0.5 s: standing
    assert red_top_right(frames[15]) > 20  # 1.5 s: "fell at 1.00 s (roll)"
    assert red_top_right(frames[15][:, :96]) == 0  # the rigid panel did not fall


def test_without_ffmpeg_a_gif_is_written_with_a_warning(model, gl, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("IMAGEIO_FFMPEG_EXE", str(tmp_path / "no-ffmpeg-here"))
    with pytest.warns(VideoWarning, match=r"MP4 not written .*; wrote block.gif instead"):
        result = write_video([sliding_block(model)], tmp_path / "block.mp4", SMALL)
    assert (result.kind, result.path) == ("gif", tmp_path / "block.gif")
    assert not (tmp_path / "block.mp4").exists()
    with Image.open(tmp_path / "block.gif") as gif:
        assert gif.n_frames == result.frames == 21
        assert gif.size == (96, 64)


def test_without_gif_either_a_keyframe_strip_is_written(model, gl, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("IMAGEIO_FFMPEG_EXE", str(tmp_path / "no-ffmpeg-here"))

    def no_gif(*args: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(video, "write_gif", no_gif)
    with pytest.warns(
        VideoWarning,
        match=r"MP4 not written \(FileNotFoundError: .*GIF not written \(OSError: disk full\); "
        r"wrote block_keyframes.png instead",
    ):
        result = write_video([sliding_block(model)], tmp_path / "block.mp4", SMALL)
    assert (result.kind, result.frames) == ("png", KEYFRAMES)
    with Image.open(tmp_path / "block_keyframes.png") as strip:
        assert strip.size == (3 * 96, 2 * 64)


def test_without_opengl_nothing_is_written_and_the_result_says_why(
    model, tmp_path: Path, monkeypatch
) -> None:
    class NoContext:
        def __init__(self, width: int, height: int) -> None:
            raise RuntimeError("eglInitialize failed")

    monkeypatch.setattr(render, "gl_context_class", lambda: NoContext)
    with pytest.warns(VideoWarning, match=r"eglInitialize failed; no video written"):
        result = write_video([sliding_block(model)], tmp_path / "block.mp4", SMALL)
    assert (result.path, result.kind, result.frames) == (None, "none", 0)
    assert result.reason is not None
    assert "no OpenGL context" in result.reason
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def headless_linux(monkeypatch: pytest.MonkeyPatch) -> pytest.MonkeyPatch:
    monkeypatch.setattr(render.sys, "platform", "linux")
    for name in ("MUJOCO_GL", "DISPLAY", "WAYLAND_DISPLAY", "PYOPENGL_PLATFORM"):
        monkeypatch.delenv(name, raising=False)
    return monkeypatch


def test_egl_is_chosen_on_a_headless_linux_machine(headless_linux: pytest.MonkeyPatch) -> None:
    assert render.select_gl_backend() == "egl"
    headless_linux.setenv("MUJOCO_GL", "GLFW")
    assert render.select_gl_backend() == "glfw"  # what the user set
    headless_linux.delenv("MUJOCO_GL")
    headless_linux.setenv("DISPLAY", ":0")
    assert render.select_gl_backend() == ""  # MuJoCo's own choice


def test_mujoco_gl_is_set_once_egl_loads(headless_linux: pytest.MonkeyPatch) -> None:
    class Context:
        pass

    headless_linux.setattr(render, "_context_class", lambda backend: Context)
    assert render.gl_context_class() is Context
    assert os.environ["MUJOCO_GL"] == "egl"  # for MuJoCo imported later, e.g. in workers


def test_mujoco_gl_is_left_alone_when_egl_cannot_load(headless_linux: pytest.MonkeyPatch) -> None:
    def no_egl(backend: str) -> None:
        os.environ["PYOPENGL_PLATFORM"] = "egl"  # as mujoco.egl does on import
        raise ImportError("libEGL.so.1: cannot open shared object file")

    headless_linux.setattr(render, "_context_class", no_egl)
    with pytest.raises(render.RendererUnavailableError, match=r"\(MUJOCO_GL=egl\): ImportError"):
        render.gl_context_class()
    assert "MUJOCO_GL" not in os.environ  # a later ``import mujoco`` must not fail on it
    assert "PYOPENGL_PLATFORM" not in os.environ


def test_a_fall_is_marked_in_red_and_labels_are_drawn() -> None:
    grey = np.full((64, 240, 3), 128, dtype=np.uint8)
    plain = label_panel(grey, "", 0.0)
    labelled = label_panel(grey, "all effects", 1.5, "fell at 1.00 s (roll)")
    red = (labelled[..., 0] > 150) & (labelled[..., 1] < 90)
    assert np.count_nonzero(red[:, 120:]) > 50
    assert np.count_nonzero(red[:, :120]) == 0
    assert np.count_nonzero(plain[:20, :60] != 128) == 0  # no label: nothing drawn there
    assert np.count_nonzero(labelled[:20, :60] != 128) > 50


def test_bad_clips_and_settings_are_named(model) -> None:
    with pytest.raises(
        ParameterError, match=r"qpos must have shape \(N >= 1, nq = 7\); got \(3, 2\)"
    ):
        MotionClip(model, np.zeros((3, 2)), np.arange(3.0))
    with pytest.raises(ParameterError, match=r"time_s must be increasing"):
        MotionClip(model, np.zeros((3, 7)), np.array([0.0, 0.0, 1.0]))
    with pytest.raises(ParameterError, match=r"width_px must be an even integer; got 95"):
        VideoSettings(width_px=95)
    with pytest.raises(ParameterError, match=r"at least one clip"):
        write_video([], "never.mp4")
    late = VideoSettings(window_s=(5.0, 6.0))
    with pytest.raises(
        ParameterError, match=r"window_s \(5.0, 6.0\) lies outside the clips' time \[0, 2\] s"
    ):
        write_video([sliding_block(model)], "never.mp4", late)
