"""Offscreen frames of a robot model in a given configuration, seen by a camera beside it.

MuJoCo's Python bindings choose their OpenGL backend once, when ``mujoco`` is first imported
(``mujoco/rendering/classic/gl_context.py`` reads ``MUJOCO_GL``: ``egl``, ``osmesa``,
``glx`` or, by default, GLFW), and ``mujoco.Renderer`` builds that backend's ``GLContext``.
GLFW needs a display, so the default fails on a headless machine, and by the time a video is
asked for zmpkit has long imported MuJoCo. :class:`OffscreenRenderer` therefore picks the
context itself (:func:`gl_context_class`): where ``MUJOCO_GL`` is unset on Linux without a
display, the EGL context is taken from ``mujoco.egl`` directly, and once it loads
``MUJOCO_GL=egl`` is set for MuJoCo imported later (e.g. in worker processes); any other
``MUJOCO_GL`` is honoured.

Frames are drawn by MuJoCo's own OpenGL renderer into its offscreen buffer (``mjr_render``,
``mjr_readPixels``) after ``mj_forward`` has placed the bodies of the given ``qpos``.
"""

from __future__ import annotations

import copy
import math
import os
import sys
from dataclasses import dataclass
from types import TracebackType
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate

__all__ = [
    "BALANCE_VIEW",
    "WALK_VIEW",
    "CameraView",
    "OffscreenRenderer",
    "RendererUnavailableError",
    "error_text",
    "gl_context_class",
    "select_gl_backend",
]

_MAX_GEOMS = 2000
_IDENTITY = np.eye(3).ravel()
_MARK_RGBA = np.array([0.25, 0.25, 0.3, 1.0], dtype=np.float32)
_MARK_SPACINGS_M = (0.05, 0.1, 0.25, 0.5, 1.0)


class RendererUnavailableError(RuntimeError):
    """No OpenGL context could be created here (no display, no EGL/OSMesa library)."""


@dataclass(frozen=True)
class CameraView:
    """Where the camera looks from, relative to the robot.

    Attributes:
        azimuth_deg: camera heading about the world z axis [deg]; 90 looks along +y, so a
            robot walking along +x crosses the image from left to right; 180 faces the robot.
        elevation_deg: camera pitch, negative looking down [deg].
        height_fraction: how much of the image height the standing robot fills [-].
        track: follow the robot's base along the floor (a walk); False: a fixed camera
            (a robot standing in place).
    """

    azimuth_deg: float = 90.0
    elevation_deg: float = -12.0
    height_fraction: float = 0.6
    track: bool = True

    def __post_init__(self) -> None:
        _validate.finite("CameraView.azimuth_deg", self.azimuth_deg)
        _validate.in_range("CameraView.elevation_deg", self.elevation_deg, -89.0, 89.0, "deg")
        _validate.in_range("CameraView.height_fraction", self.height_fraction, 0.05, 1.0, "-")


WALK_VIEW = CameraView(azimuth_deg=110.0, elevation_deg=-12.0, height_fraction=0.55, track=True)
"""A walk seen from its left side, slightly from the front, following the robot."""
BALANCE_VIEW = CameraView(azimuth_deg=90.0, elevation_deg=-8.0, height_fraction=0.7, track=False)
"""A robot balancing in place, seen from its left side (a sagittal lean)."""


def select_gl_backend() -> str:
    """The OpenGL backend for offscreen rendering.

    ``MUJOCO_GL`` (lower case) when set; else ``egl`` on Linux with neither ``DISPLAY`` nor
    ``WAYLAND_DISPLAY`` (GLFW, MuJoCo's default, cannot start without a display); else ``""``
    (MuJoCo's choice).
    """
    backend = os.environ.get("MUJOCO_GL", "").strip().lower()
    headless = not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    if not backend and sys.platform.startswith("linux") and headless:
        return "egl"
    return backend


def gl_context_class() -> Any:
    """The ``GLContext`` class of :func:`select_gl_backend`'s backend.

    Once EGL's context loads for a headless machine, ``MUJOCO_GL=egl`` is set for the
    processes started later; if it does not load, the environment is left as it was (a
    ``MUJOCO_GL`` naming a backend that cannot load stops ``import mujoco`` itself).

    Raises:
        RendererUnavailableError: if the backend's libraries cannot be loaded.
    """
    backend = select_gl_backend()
    saved = {name: os.environ.get(name) for name in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    try:
        context_class = _context_class(backend)
    except Exception as exc:  # ImportError, OSError, PyOpenGL errors: no usable GL here
        for name, value in saved.items():  # mujoco.egl sets PYOPENGL_PLATFORM on import
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
        raise RendererUnavailableError(_why("MUJOCO_GL", backend or "glfw", exc)) from exc
    if backend:
        os.environ.setdefault("MUJOCO_GL", backend)
    return context_class


def _context_class(backend: str) -> Any:
    """Import the ``GLContext`` of ``backend`` (``egl``, ``osmesa``, else MuJoCo's own)."""
    if backend == "egl":
        from mujoco.egl import GLContext
    elif backend == "osmesa":
        from mujoco.osmesa import GLContext
    else:
        from mujoco import GLContext
    return GLContext


def _why(what: str, backend: str, exc: BaseException) -> str:
    return f"no OpenGL context ({what}={backend}): {error_text(exc, 120)}"


def error_text(exc: BaseException, limit: int = 120) -> str:
    """``exc`` as one short line, ``"Kind: message"``, cut to ``limit`` characters."""
    message = " ".join(str(exc).split())
    text = f"{type(exc).__name__}: {message}" if message else type(exc).__name__
    return text if len(text) <= limit else text[: limit - 3] + "..."


class OffscreenRenderer:
    """Draws one model's configurations offscreen, ``width_px`` × ``height_px`` RGB.

    Args:
        model: the robot's model; not modified (the renderer draws a copy with an offscreen
            buffer of at least the image size and a brighter headlight).
        width_px: image width [px].
        height_px: image height [px].

    Raises:
        RendererUnavailableError: if no OpenGL context can be created.
    """

    def __init__(self, model: mujoco.MjModel, width_px: int, height_px: int) -> None:
        self.width_px, self.height_px = width_px, height_px
        self.model = _render_model(model, width_px, height_px)
        self.data = mujoco.MjData(self.model)
        context_class = gl_context_class()
        try:
            self._context = context_class(width_px, height_px)
            self._context.make_current()
            self._mjr = mujoco.MjrContext(self.model, mujoco.mjtFontScale.mjFONTSCALE_100)
        except Exception as exc:  # EGL/GLFW initialisation errors of any kind
            raise RendererUnavailableError(_why("MUJOCO_GL", select_gl_backend(), exc)) from exc
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._mjr)
        self._scene = mujoco.MjvScene(self.model, maxgeom=_MAX_GEOMS)
        self._scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False  # 2x faster in software GL
        self._scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = False
        self._option = mujoco.MjvOption()
        self._camera = mujoco.MjvCamera()
        self._rect = mujoco.MjrRect(0, 0, width_px, height_px)
        self._rgb = np.empty((height_px, width_px, 3), dtype=np.uint8)
        self.mark_spacing_m = 0.1

    def fit_to_robot(self, qpos: NDArray[np.float64]) -> float:
        """Space the floor marks for the robot standing in ``qpos``; return its height.

        Returns:
            The height of the robot's highest point above the floor [m], at least 0.1 m;
            the marks are about a fifth of it apart (:attr:`mark_spacing_m`).
        """
        self._place(qpos)
        robot = self.model.geom_bodyid != 0
        top = self.data.geom_xpos[robot, 2] + self.model.geom_rbound[robot]
        height = float(max(np.max(top, initial=0.0), 0.1))
        self.mark_spacing_m = min(_MARK_SPACINGS_M, key=lambda s: abs(math.log(s * 5 / height)))
        return height

    def render(
        self, qpos: NDArray[np.float64], lookat_m: NDArray[np.float64], distance_m: float,
        view: CameraView,
    ) -> NDArray[np.uint8]:  # fmt: skip
        """Draw the model in configuration ``qpos``.

        Args:
            qpos: the model's configuration, shape (nq,).
            lookat_m: the point the camera looks at, world frame [m], shape (3,).
            distance_m: camera distance from ``lookat_m`` [m].
            view: the camera's heading and pitch.

        Returns:
            The image, shape (height_px, width_px, 3), top row first.
        """
        self._place(qpos)
        camera = self._camera
        camera.lookat[:] = lookat_m
        camera.distance = distance_m
        camera.azimuth, camera.elevation = view.azimuth_deg, view.elevation_deg
        self._context.make_current()
        mujoco.mjv_updateScene(
            self.model, self.data, self._option, None, camera, mujoco.mjtCatBit.mjCAT_ALL,
            self._scene,
        )  # fmt: skip
        self._floor_marks(camera.lookat, distance_m)
        mujoco.mjr_render(self._rect, self._scene, self._mjr)
        mujoco.mjr_readPixels(self._rgb, None, self._rect, self._mjr)
        return np.flipud(self._rgb).copy()

    def _floor_marks(self, lookat_m: NDArray[np.float64], distance_m: float) -> None:
        """Draw lines across the floor every :attr:`mark_spacing_m` [m].

        A camera that follows the robot sees the floor move by them (MuJoCo's plain floor
        shows no motion).
        """
        spacing, scene = self.mark_spacing_m, self._scene
        first = math.floor((lookat_m[0] - 1.5 * distance_m) / spacing)
        last = math.ceil((lookat_m[0] + 1.5 * distance_m) / spacing)
        half = np.array([0.03 * spacing, 0.5 * distance_m, 0.0005])
        for k in range(first, last + 1):
            if scene.ngeom >= scene.maxgeom:
                return
            centre = np.array([k * spacing, lookat_m[1], 0.0005])
            mujoco.mjv_initGeom(
                scene.geoms[scene.ngeom], mujoco.mjtGeom.mjGEOM_BOX, half, centre,
                _IDENTITY, _MARK_RGBA,
            )  # fmt: skip
            scene.ngeom += 1

    def _place(self, qpos: NDArray[np.float64]) -> None:
        self.data.qpos[:] = qpos
        self.data.qvel[:] = 0.0
        mujoco.mj_forward(self.model, self.data)

    def close(self) -> None:
        """Free the OpenGL resources (idempotent)."""
        context, self._context = getattr(self, "_context", None), None
        mjr, self._mjr = getattr(self, "_mjr", None), None
        if context is None:
            return
        if mjr is not None:
            context.make_current()
            mjr.free()
        context.free()

    def __enter__(self) -> OffscreenRenderer:
        """Use as a context manager; :meth:`close` on exit."""
        return self

    def __exit__(
        self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        """Free the OpenGL resources."""
        self.close()


def _render_model(model: mujoco.MjModel, width_px: int, height_px: int) -> mujoco.MjModel:
    """A copy of ``model`` to draw.

    Its offscreen buffer holds at least the image [px]; no multisampling; a brighter headlight.
    """
    _validate.in_range("video width_px", width_px, 16, 4096, "px")
    _validate.in_range("video height_px", height_px, 16, 4096, "px")
    render = copy.deepcopy(model)
    globals_ = render.vis.global_
    globals_.offwidth = max(globals_.offwidth, width_px)
    globals_.offheight = max(globals_.offheight, height_px)
    render.vis.quality.offsamples = 0  # 4x multisampling triples software OpenGL's cost
    render.vis.headlight.ambient[:] = np.maximum(render.vis.headlight.ambient, 0.35)
    render.vis.headlight.diffuse[:] = np.maximum(render.vis.headlight.diffuse, 0.55)
    return render
