"""The pipelines' videos: ``walk --video`` and two walks side by side, a fall included."""

from __future__ import annotations

from pathlib import Path

import imageio_ffmpeg
import numpy as np
import pytest

from helpers.gl import skip_without_gl
from zmpkit.analysis.walk_video import WALK_VIDEO, effects_label, write_walks_side_by_side
from zmpkit.cli import main
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_disturbances import Push
from zmpkit.pipelines.walk import run_walk
from zmpkit.robots.registry import get_robot


def frames_of(path: Path) -> tuple[tuple[int, int], list[np.ndarray]]:
    reader = imageio_ffmpeg.read_frames(str(path))
    width, height = next(reader)["size"]
    return (width, height), [np.frombuffer(f, np.uint8).reshape(height, width, 3) for f in reader]


def fall_mark_pixels(panel: np.ndarray) -> int:
    """Red pixels of the "fell at ..." box in a panel's top-right corner."""
    corner = panel[:24, -150:].astype(int)
    return int(np.count_nonzero((corner[..., 0] > 150) & (corner[..., 1] < 90)))


@pytest.mark.slow
def test_walk_video_writes_walk_mp4_and_says_where(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    skip_without_gl()
    out = tmp_path / "walk"
    code = main(["walk", "--effects", "none", "--duration", "1", "--controller", "open",
                 "--video", "--out", str(out)])  # fmt: skip
    assert code == 0
    assert f"video: {out / 'walk.mp4'}" in capsys.readouterr().out
    size, frames = frames_of(out / "walk.mp4")
    assert size == (WALK_VIDEO.width_px, WALK_VIDEO.height_px)
    with (out / "timeseries.csv").open() as f:
        recorded_s = float(list(f)[-1].split(",")[0])
    assert len(frames) == pytest.approx(recorded_s * WALK_VIDEO.fps + 1, abs=1)  # every 40 ms
    assert np.abs(frames[-1].astype(int) - frames[0].astype(int)).mean() > 0.5  # it moved


@pytest.mark.slow
def test_a_walk_has_no_video_unless_asked(tmp_path: Path) -> None:
    out = tmp_path / "walk"
    assert main(["walk", "--effects", "none", "--duration", "0.5", "--step-duration", "0.5",
                 "--controller", "open", "--out", str(out)]) == 0  # fmt: skip
    assert (out / "summary.json").exists()
    assert not list(out.glob("walk.*"))


@pytest.mark.slow
def test_rigid_and_fallen_walks_side_by_side(tmp_path: Path) -> None:
    skip_without_gl()
    rigid = WalkConfig(get_robot("nao"), duration_s=2.0, effects="none", figures=False)
    pushed = WalkConfig(
        get_robot("nao"),
        duration_s=2.0,
        effects="none",
        figures=False,
        pushes=(Push(60.0, 1.5, "y"),),
    )
    walks = [(c, run_walk(c).record) for c in (rigid, pushed)]
    assert walks[1][1].fell  # the push throws it over
    result = write_walks_side_by_side(walks, tmp_path / "both.mp4")
    size, frames = frames_of(tmp_path / "both.mp4")
    assert size == (2 * WALK_VIDEO.width_px, WALK_VIDEO.height_px)
    assert size == (result.width_px, result.height_px)
    assert len(frames) == result.frames
    assert result.frames == pytest.approx(walks[0][1].time_s[-1] * WALK_VIDEO.fps + 1, abs=1)
    panel = WALK_VIDEO.width_px
    left, right = frames[-1][:, :panel], frames[-1][:, panel:]
    assert fall_mark_pixels(right) > 100
    assert fall_mark_pixels(left) == 0
    assert fall_mark_pixels(frames[0][:, panel:]) == 0  # not before the fall


@pytest.mark.parametrize(
    ("effects", "label"), [("none", "rigid"), ("all", "all effects"), ("M,I", "effects M,I")]
)
def test_panels_name_their_effects(effects: str, label: str) -> None:
    assert effects_label(effects) == label


@pytest.mark.parametrize(("command", "default"), [("walk", "no-video"), ("balance", "no-video"),
                                                  ("demo", "video")])  # fmt: skip
def test_video_is_on_by_default_only_in_the_demo(
    command: str, default: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([command, "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "--video / --no-video" in text
    assert f"[default: {default}]" in text.split("--video / --no-video", 1)[1]
