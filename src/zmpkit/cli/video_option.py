"""The ``--video/--no-video`` option of the commands that can film their robot."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import click

__all__ = ["video_option"]

_F = TypeVar("_F", bound=Callable[..., Any])


def video_option(default: bool, what: str) -> Callable[[_F], _F]:
    """``--video/--no-video``: whether to draw ``what`` as a video after the simulation.

    Args:
        default: on or off when not given.
        what: what the video shows and where it goes, e.g. ``"the walk (walk.mp4)"``.
    """
    return click.option(
        "--video/--no-video",
        default=default,
        show_default=True,
        help=f"Draw {what} as an MP4 after the simulation (MuJoCo's offscreen renderer; a "
        "GIF or keyframes where MP4 cannot be written, nothing without OpenGL).",
    )
