"""Video frames into files: an MP4 (ffmpeg), or a GIF or a keyframe strip (Pillow); labels.

Everything here takes RGB frames, shape (H, W, 3), and needs no OpenGL: it is how
:mod:`zmpkit.analysis.video` labels its frames and writes them, MP4 first and the others
where an MP4 cannot be written.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageDraw, ImageFont

__all__ = ["GIF_MAX_FPS", "KEYFRAMES", "keyframe_strip", "label_panel", "write_gif", "write_mp4"]

GIF_MAX_FPS = 10.0
"""A GIF's frames are decimated to at most this rate [1/s]: GIFs are large and slow to encode."""
KEYFRAMES = 6
"""Frames shown by a keyframe strip [-]."""
_STRIP_COLUMNS = 3
_TEXT_RGB = (255, 255, 255)
_BOX_RGB = (20, 20, 20)
_FALL_RGB = (200, 30, 30)


@lru_cache(maxsize=8)
def _font(size_px: int) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """Pillow's default font at ``size_px`` [px] (its bitmap font on Pillow < 10.1)."""
    try:
        return ImageFont.load_default(size=size_px)
    except TypeError:  # Pillow < 10.1: one fixed size
        return ImageFont.load_default()


def label_panel(
    image: NDArray[np.uint8], label: str, time_s: float, fall_text: str | None = None
) -> NDArray[np.uint8]:
    """Label a frame: its panel's name, its time and, once fallen, the fall.

    ``label`` goes at the top left, the time at the bottom left, ``fall_text`` in a red box
    at the top right.

    Args:
        image: an RGB frame, shape (H, W, 3).
        label: the panel's name, e.g. ``"all effects"``; empty: none.
        time_s: the frame's time [s].
        fall_text: e.g. ``"fell at 4.32 s (roll)"``, shown once the robot has fallen.
    """
    picture = Image.fromarray(image)
    draw = ImageDraw.Draw(picture)
    height = image.shape[0]
    font = _font(max(10, height // 16))
    margin = max(2, height // 60)
    if label:
        _text_box(draw, (margin, margin), label, font, _BOX_RGB)
    bottom = height - margin - _text_height(draw, "t", font) - 2 * margin
    _text_box(draw, (margin, bottom), f"t = {time_s:5.2f} s", font, _BOX_RGB)
    if fall_text:
        width = draw.textbbox((0, 0), fall_text, font=font)[2] + 2 * margin
        _text_box(draw, (image.shape[1] - width - margin, margin), fall_text, font, _FALL_RGB)
    return np.asarray(picture)


def _text_height(
    draw: ImageDraw.ImageDraw, text: str, font: ImageFont.ImageFont | ImageFont.FreeTypeFont
) -> int:
    """The height of ``text`` in ``font`` [px]."""
    box = draw.textbbox((0, 0), text, font=font)
    return int(box[3] - box[1])


def _text_box(
    draw: ImageDraw.ImageDraw,
    at: tuple[int, int],
    text: str,
    font: ImageFont.ImageFont | ImageFont.FreeTypeFont,
    fill: tuple[int, int, int],
) -> None:
    """``text`` in white on a filled box whose top-left corner is ``at`` [px]."""
    x, y = at
    pad = 3
    _, _, right, bottom = draw.textbbox((x + pad, y + pad), text, font=font)
    draw.rectangle((x, y, right + pad, bottom + pad), fill=fill)
    draw.text((x + pad, y + pad), text, font=font, fill=_TEXT_RGB)


def write_mp4(
    frames: Iterator[NDArray[np.uint8]], path: Path, fps: float, size: tuple[int, int]
) -> None:
    """Encode RGB ``frames`` of ``size`` (width, height) [px] at ``fps`` [1/s] into ``path``.

    H.264, ``yuv420p`` and the index at the front (``+faststart``): what browsers play.
    """
    import imageio_ffmpeg  # type: ignore[import-untyped]

    writer = imageio_ffmpeg.write_frames(
        str(path), size, fps=fps, codec="libx264", pix_fmt_out="yuv420p", macro_block_size=2,
        quality=6, ffmpeg_log_level="error", output_params=["-movflags", "+faststart"],
    )  # fmt: skip
    writer.send(None)
    try:
        for frame in frames:
            writer.send(np.ascontiguousarray(frame))
    finally:
        writer.close()


def write_gif(frames: Iterable[NDArray[np.uint8]], path: Path, fps: float) -> tuple[int, float]:
    """Write ``frames`` (at ``fps`` [1/s]) as a looping GIF at no more than :data:`GIF_MAX_FPS`.

    Returns:
        The frames written [-] and the GIF's frame rate [1/s].
    """
    every = max(1, math.ceil(fps / GIF_MAX_FPS))
    images = [Image.fromarray(f) for k, f in enumerate(frames) if k % every == 0]
    if not images:
        raise ValueError("no frames to write")
    gif_fps = fps / every
    images[0].save(
        path, save_all=True, append_images=images[1:], duration=round(1000.0 / gif_fps), loop=0
    )
    return len(images), gif_fps


def keyframe_strip(frames: Iterable[NDArray[np.uint8]], count: int, path: Path) -> int:
    """Write :data:`KEYFRAMES` frames spread evenly over the ``count`` frames as a PNG grid.

    Returns:
        The keyframes shown [-].
    """
    wanted = set(np.linspace(0, count - 1, min(KEYFRAMES, count)).round().astype(int).tolist())
    keys = [f for k, f in enumerate(frames) if k in wanted]
    if not keys:
        raise ValueError("no frames to show")
    rows = math.ceil(len(keys) / _STRIP_COLUMNS)
    columns = min(len(keys), _STRIP_COLUMNS)
    height, width = keys[0].shape[:2]
    grid = np.full((rows * height, columns * width, 3), 255, dtype=np.uint8)
    for k, frame in enumerate(keys):
        row, column = divmod(k, _STRIP_COLUMNS)
        grid[row * height : (row + 1) * height, column * width : (column + 1) * width] = frame
    Image.fromarray(grid).save(path)
    return len(keys)
