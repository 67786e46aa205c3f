"""Skip a test where no offscreen OpenGL context can be created (no EGL library, no display).

Videos need one; everything else about them (fallbacks, labels) is tested without it.
"""

from __future__ import annotations

import mujoco
import pytest

from zmpkit.analysis.render import OffscreenRenderer, RendererUnavailableError

__all__ = ["skip_without_gl"]

_SCENE = "<mujoco><worldbody><geom type='sphere' size='0.1'/></worldbody></mujoco>"


def skip_without_gl() -> None:
    """``pytest.skip`` with the reason when MuJoCo's offscreen renderer cannot start here."""
    try:
        OffscreenRenderer(mujoco.MjModel.from_xml_string(_SCENE), 32, 32).close()
    except RendererUnavailableError as exc:
        pytest.skip(f"no offscreen OpenGL context here: {exc}")
