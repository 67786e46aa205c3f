"""Where a force–torque sensor sits on a foot: its pose in the world and its height above the sole.

A :class:`SensorMount` is the geometry that turns a sensor-frame wrench into a centre of
pressure on the ground (see :mod:`zmpkit.sensors.zmp`):

- ``position``: the sensor origin ``o`` in the world frame [m];
- ``rotation``: the sensor→world rotation matrix ``R`` (a vector ``v_sensor`` in the sensor
  frame is ``R @ v_sensor`` in the world frame);
- ``sole_height``: ``h``, the height of the sensor origin above the ground plane under the
  sole [m], so that the sole touches the plane ``z = o_z - h`` (:attr:`SensorMount.ground_height`).

On paper A's robot the JR3 frames are rotated π about x (sensor z points down) and sit about
0.01 m above the sole (inferred, not stated; see the robot's parameter notes, §5), e.g.
``SensorMount.from_rpy((0, -0.1285, 0.01), (math.pi, 0, 0), sole_height=0.01, name="right")``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite_array, non_negative
from zmpkit.errors import ParameterError

__all__ = [
    "ROTATION_TOLERANCE",
    "ROTATION_ZERO_SNAP",
    "SensorMount",
    "rpy_to_matrix",
    "wrench_in_world",
]

ROTATION_TOLERANCE = 1e-6
"""Largest accepted ``max |RᵀR − I|`` and ``|det R − 1|`` of a mounting rotation [-]."""

ROTATION_ZERO_SNAP = 1e-15
"""Entries of :func:`rpy_to_matrix` smaller than this in magnitude are set to exactly 0 [-].

``math.sin(math.pi)`` is 1.2e-16, not 0; snapping that residue keeps the matrix of a
quarter- or half-turn exact, so the scalar fast path can drop its zero coefficients.
"""


def _rot_x(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_y(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rot_z(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rpy_to_matrix(rpy: ArrayLike) -> NDArray[np.float64]:
    r"""Rotation matrix of roll–pitch–yaw angles.

    .. math:: R = R_z(\text{yaw})\, R_y(\text{pitch})\, R_x(\text{roll})

    i.e. rotate about the fixed x axis by roll, then about fixed y by pitch, then about fixed
    z by yaw (the URDF/SDF ``rpy`` convention). Entries smaller than
    :data:`ROTATION_ZERO_SNAP` in magnitude are set to exactly 0.

    Args:
        rpy: (roll, pitch, yaw) [rad].

    Returns:
        (3, 3) rotation matrix [-].
    """
    roll, pitch, yaw = finite_array("rpy", rpy, (3,))
    rotation = _rot_z(yaw) @ _rot_y(pitch) @ _rot_x(roll)
    rotation[np.abs(rotation) < ROTATION_ZERO_SNAP] = 0.0
    return rotation


def _check_rotation(rotation: NDArray[np.float64]) -> None:
    """Raise unless ``rotation`` is orthonormal with det +1 within :data:`ROTATION_TOLERANCE`."""
    error = float(np.max(np.abs(rotation.T @ rotation - np.eye(3))))
    if error > ROTATION_TOLERANCE:
        raise ParameterError(
            f"rotation must be orthonormal (max |R^T R - I| <= {ROTATION_TOLERANCE}), "
            f"got max |R^T R - I| = {error:.3g}"
        )
    det = float(np.linalg.det(rotation))
    if abs(det - 1.0) > ROTATION_TOLERANCE:
        raise ParameterError(
            f"rotation must have det +1 (a proper rotation, not a reflection), got det = {det:.6g}"
        )


def _frozen(array: NDArray[np.float64]) -> NDArray[np.float64]:
    array = array.copy()
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class SensorMount:
    """Pose of one ankle force–torque sensor and its height above the sole.

    Attributes:
        position: sensor origin ``o`` in the world frame, shape (3,) [m].
        rotation: sensor→world rotation matrix ``R``, shape (3, 3) [-]; orthonormal with
            det +1 within :data:`ROTATION_TOLERANCE`.
        sole_height: height ``h`` of the sensor origin above the ground plane under the sole
            [m], >= 0.
        name: label used in messages and reports, e.g. ``"right"``.

    Raises:
        ParameterError: on a wrong shape, a non-finite value, a rotation that is not a proper
            rotation, or a negative ``sole_height``.
    """

    position: NDArray[np.float64]
    rotation: NDArray[np.float64]
    sole_height: float
    name: str = ""

    def __post_init__(self) -> None:
        position = finite_array("position", self.position, (3,))
        rotation = finite_array("rotation", self.rotation, (3, 3))
        _check_rotation(rotation)
        sole_height = non_negative("sole_height", self.sole_height, "m")
        object.__setattr__(self, "position", _frozen(position))
        object.__setattr__(self, "rotation", _frozen(rotation))
        object.__setattr__(self, "sole_height", sole_height)
        object.__setattr__(self, "name", str(self.name))

    @classmethod
    def from_rpy(
        cls, position: ArrayLike, rpy: ArrayLike, sole_height: float, name: str = ""
    ) -> SensorMount:
        """Mount from a position and roll–pitch–yaw angles.

        Args:
            position: sensor origin in the world frame, shape (3,) [m].
            rpy: (roll, pitch, yaw) of the sensor frame w.r.t. the world [rad];
                ``R = Rz(yaw) · Ry(pitch) · Rx(roll)`` (see :func:`rpy_to_matrix`).
            sole_height: height of the sensor origin above the sole [m].
            name: label, e.g. ``"right"``.
        """
        return cls(np.asarray(position), rpy_to_matrix(rpy), sole_height, name)

    @property
    def ground_height(self) -> float:
        """Height of the ground plane under the sole, ``o_z − h``, in the world frame [m]."""
        return float(self.position[2]) - self.sole_height

    def __repr__(self) -> str:
        return (
            f"SensorMount(position={self.position.tolist()}, rotation={self.rotation.tolist()}, "
            f"sole_height={self.sole_height}, name={self.name!r})"
        )


def wrench_in_world(
    sensor_xmat: NDArray[np.float64], wrench: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Force [N] and moment [N·m] of sensor-frame wrenches in the world frame.

    ``F = R F_s``, ``τ_o = R τ_s``: the moment stays about the sensor origin ``o``.

    Args:
        sensor_xmat: the sensor frames' sensor→world rotations ``R``, row-major (as MuJoCo's
            ``site_xmat``), shape (..., 9).
        wrench: (F_x, F_y, F_z, τ_x, τ_y, τ_z) in the sensor frame [N, N·m], shape (..., 6).
    """
    rotation = np.reshape(sensor_xmat, (*np.shape(sensor_xmat)[:-1], 3, 3))
    force = np.einsum("...ij,...j->...i", rotation, wrench[..., :3])
    return force, np.einsum("...ij,...j->...i", rotation, wrench[..., 3:])
