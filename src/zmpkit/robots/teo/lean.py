"""Joint targets that lean the standing TEO in one plane while both feet stay flat.

Paper A's push-recovery steps (§4.1) lean the whole robot about its ankles:

- **sagittal**: both ankle pitch joints (``*_ankle_frontal``, axis y) turn by the same angle;
  everything above the ankles rotates rigidly, so the lean is exactly that angle.
- **frontal**: both ankle roll joints (``*_ankle_sagittal``, axis x) and the hip roll joints
  (``*_hip_sagittal``) turn so that the legs tilt sideways and the feet stay flat. TEO's
  legs are not parallel (each ankle sits :data:`~zmpkit.robots.teo.geometry.KNEE_TO_ANKLE_LATERAL_M`
  inward of its hip), so the two legs and the pelvis form a trapezoidal four-bar, not a
  parallelogram: the legs tilt by slightly different angles and the pelvis rolls a little.
  Commanding the same ankle roll and the opposite hip roll on both legs would ask the
  closed chain for incompatible foot heights (≈ 2 · 0.0175 m · sin θ) and make stiff joint
  servos fight each other through the floor.

In the frontal plane the four-bar is solved in closed form in the y–z plane: ankles at
``(∓d_a, 0)``, leg vectors ``u = (±w, l)`` from ankle to hip axis, hips ``2 d_h`` apart. For a
lean ``θ`` [rad] (positive = toward +y, the left) the legs tilt by ``φ_R, φ_L`` about +x with
mean ``−θ`` and hip distance ``2 d_h``; the pelvis roll is the angle of the hip-to-hip line.
Only design geometry is used (no truth parameters).
"""

from __future__ import annotations

import math

from zmpkit.errors import ParameterError
from zmpkit.robots.teo import geometry as geo

__all__ = ["LEAN_PLANES", "frontal_four_bar", "teo_lean_joints"]

LEAN_PLANES: tuple[str, str] = ("sagittal", "frontal")
"""The planes a lean can be in."""

_ANKLE_Y_M = geo.HIP_LATERAL_M - geo.KNEE_TO_ANKLE_LATERAL_M
_LEG_M = geo.THIGH_M + geo.SHANK_M
_NEWTON_STEPS = 8


def _rotate(y: float, z: float, angle: float) -> tuple[float, float]:
    """Rotate the y–z vector about +x by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return c * y - s * z, s * y + c * z


def _hips(phi_right: float, phi_left: float) -> tuple[tuple[float, float], tuple[float, float]]:
    """Hip-axis points (y, z) [m] of the right and left leg tilted by their angles [rad]."""
    w = geo.KNEE_TO_ANKLE_LATERAL_M
    ry, rz = _rotate(-w, _LEG_M, phi_right)
    ly, lz = _rotate(w, _LEG_M, phi_left)
    return (-_ANKLE_Y_M + ry, rz), (_ANKLE_Y_M + ly, lz)


def _hip_gap_error(mean: float, half_diff: float) -> float:
    (ry, rz), (ly, lz) = _hips(mean + half_diff, mean - half_diff)
    return math.hypot(ly - ry, lz - rz) - 2.0 * geo.HIP_LATERAL_M


def frontal_four_bar(angle: float) -> tuple[float, float, float]:
    """Leg tilts and pelvis roll of a frontal lean by ``angle`` [rad] (positive toward +y).

    Returns:
        ``(phi_right, phi_left, pelvis_roll)`` [rad], rotations about +x in the world.
    """
    mean, half = -angle, 0.0
    for _ in range(_NEWTON_STEPS):
        err = _hip_gap_error(mean, half)
        slope = (_hip_gap_error(mean, half + 1e-7) - _hip_gap_error(mean, half - 1e-7)) / 2e-7
        if slope == 0.0 or abs(err) < 1e-15:
            break
        half -= err / slope
    (ry, rz), (ly, lz) = _hips(mean + half, mean - half)
    return mean + half, mean - half, math.atan2(lz - rz, ly - ry)


def teo_lean_joints(plane: str, angle: float) -> dict[str, float]:
    """Joint targets [rad] of a lean by ``angle`` [rad], feet flat, all other joints at 0.

    Args:
        plane: ``"sagittal"`` (positive = forward, +x) or ``"frontal"`` (positive = left, +y).
        angle: the lean angle of the legs about the ankles [rad].

    Raises:
        ParameterError: on an unknown plane or a non-finite angle.
    """
    if not math.isfinite(angle):
        raise ParameterError(f"lean angle must be finite, got {angle!r}")
    if plane == "sagittal":
        return {"right_ankle_frontal": -angle, "left_ankle_frontal": -angle}
    if plane == "frontal":
        phi_r, phi_l, roll = frontal_four_bar(angle)
        return {
            "right_hip_sagittal": phi_r - roll,
            "right_ankle_sagittal": -phi_r,
            "left_hip_sagittal": phi_l - roll,
            "left_ankle_sagittal": -phi_l,
        }
    raise ParameterError(f"unknown lean plane {plane!r}; valid: {', '.join(LEAN_PLANES)}")
