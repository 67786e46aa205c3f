r"""Trunk pitch and roll from an IMU's orientation estimate.

An orientation quaternion ``(w, x, y, z)`` (world ← body) gives ZYX Euler angles; pitch
about y, roll about x:

.. math:: \theta = \arcsin(2 (w y - z x)), \qquad
    \phi = \operatorname{atan2}(2 (w x + y z),\; 1 - 2 (x^2 + y^2)).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["quaternion_pitch_roll", "quaternion_yaw", "tilt_from_quaternions"]


def _pitch(w: float, x: float, y: float, z: float) -> float:
    return math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))


def _roll(w: float, x: float, y: float, z: float) -> float:
    return math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))


def quaternion_pitch_roll(quat_wxyz: NDArray[np.float64]) -> tuple[float, float]:
    """Pitch and roll [rad] of an orientation (ZYX Euler angles; pitch about y)."""
    q = np.asarray(quat_wxyz)  # the array itself when given one: nothing allocated
    w, x, y, z = q.item(0), q.item(1), q.item(2), q.item(3)
    return _pitch(w, x, y, z), _roll(w, x, y, z)


def quaternion_yaw(quat_wxyz: NDArray[np.float64]) -> float:
    """Yaw [rad] of an orientation (ZYX Euler angles; about the world z axis), in (−π, π].

    ψ = atan2(2(w z + x y), 1 − 2(y² + z²)).
    """
    q = np.asarray(quat_wxyz)  # the array itself when given one: nothing allocated
    w, x, y, z = q.item(0), q.item(1), q.item(2), q.item(3)
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def tilt_from_quaternions(quat_wxyz: NDArray[np.float64], plane: str) -> NDArray[np.float64]:
    """Trunk pitch (``plane="sagittal"``) or roll (otherwise) of IMU quaternions [rad], (N,).

    Args:
        quat_wxyz: orientations (w, x, y, z), shape (N, 4).
        plane: ``"sagittal"`` for pitch, ``"frontal"`` for roll.
    """
    angle = _pitch if plane == "sagittal" else _roll
    rows = np.asarray(quat_wxyz, dtype=np.float64).reshape(-1, 4).tolist()
    return np.array([angle(w, x, y, z) for w, x, y, z in rows], dtype=np.float64)
