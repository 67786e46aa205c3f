r"""The observer of the ZMP/IP walk: the cart-table state corrected by the measured CoM and ZMP.

Czarnetzki, Kerner and Urbann ("Observer-based dynamic walking control for biped robots",
Robotics and Autonomous Systems 57, 2009), the controller of paper B's walking robot, run the
preview controller of :mod:`zmpkit.walking.preview` on an *observed* state: each control
period the cart-table state is corrected towards the CoM and the ZMP the robot measures, so
the CoM plan reacts to what the robot really does. zmpkit adds one state to their cart
table, a slowly varying ZMP offset ``d`` (the multibody robot's ZMP minus the cart table's),
so that a steady deviation is estimated and removed rather than fought by the CoM. Per
horizontal axis, state ``z = (c, ċ, c̈, d)`` [m, m/s, m/s², m], jerk input ``u`` [m/s³]:

.. math::

    z_{k+1} = \begin{bmatrix} A & 0 \\ 0 & 1 \end{bmatrix} z_k
        + \begin{bmatrix} B \\ 0 \end{bmatrix} u_k + w_k, \qquad
    y_k = \begin{bmatrix} c \\ p \end{bmatrix}_k
        = \begin{bmatrix} 1 & 0 & 0 & 0 \\ 1 & 0 & -z_c/g & 1 \end{bmatrix} z_k + v_k

with ``A, B`` of :func:`~zmpkit.walking.cart_table.cart_table_matrices`. The observer is the
steady-state Kalman filter of this model: process noise ``w`` with covariance
``Q = σ_u² B_z B_zᵀ + diag(0, 0, 0, σ_d²)`` (an unmodelled jerk of ``σ_u`` [m/s³] per period
and a drift of the offset of ``σ_d`` [m] per period), measurement noise ``v`` with covariance
``R = diag(σ_c², σ_p²)`` (the kinematic CoM estimate and the F-T ZMP). With ``P`` the
solution of the filter's discrete algebraic Riccati equation, the gain is

.. math:: L = P C^T (C P C^T + R)^{-1}, \qquad
    \hat z^+_k = \hat z^-_k + L (y_k - C \hat z^-_k),

and the preview law then tracks ``p^{ref} - \hat d`` with the cart table, so that the
measured ZMP ``C_3 x + d`` tracks ``p^{ref}``. Its prediction ``\hat z^-_{k+1} = A_z \hat
z^+_k + B_z u_k`` is the next period's prior.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.walking.cart_table import PreviewGains, cart_table_matrices

__all__ = ["ObservedPreviewControl", "ZmpObserverParameters", "observer_gain", "observer_matrices"]


@dataclass(frozen=True)
class ZmpObserverParameters:
    """Noise levels that set the observer's gain (zmpkit's defaults; the paper gives none).

    Attributes:
        com_noise_m: σ_c, error of the kinematic CoM estimate [m].
        zmp_noise_m: σ_p, error of the measured ZMP against the cart table [m].
        jerk_noise_mps3: σ_u, unmodelled CoM jerk per period [m/s³].
        offset_drift_m: σ_d, change of the ZMP offset per period [m].
        max_offset_m: the estimated offset is clamped to ±this [m].
    """

    com_noise_m: float = 0.02
    zmp_noise_m: float = 0.02
    jerk_noise_mps3: float = 1.0
    offset_drift_m: float = 0.0005
    max_offset_m: float = 0.03

    def __post_init__(self) -> None:
        for name in ("com_noise_m", "zmp_noise_m", "jerk_noise_mps3", "offset_drift_m"):
            _validate.positive(f"ZmpObserverParameters.{name}", getattr(self, name))
        _validate.positive("ZmpObserverParameters.max_offset_m", self.max_offset_m, "m")


def observer_matrices(
    period_s: float, com_height_m: float, gravity_mps2: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``A_z`` (4, 4), ``B_z`` (4,) and ``C`` (2, 4) of the module docstring."""
    a, b, c = cart_table_matrices(period_s, com_height_m, gravity_mps2)
    a_z = np.eye(4)
    a_z[:3, :3] = a
    b_z = np.zeros(4)
    b_z[:3] = b
    c_z = np.array([[1.0, 0.0, 0.0, 0.0], [*c, 1.0]])
    return a_z, b_z, c_z


def observer_gain(
    parameters: ZmpObserverParameters,
    period_s: float,
    com_height_m: float,
    gravity_mps2: float,
) -> NDArray[np.float64]:
    """The steady-state Kalman gain ``L`` [-], shape (4, 2), columns CoM and ZMP."""
    a_z, b_z, c_z = observer_matrices(period_s, com_height_m, gravity_mps2)
    q = parameters.jerk_noise_mps3**2 * np.outer(b_z, b_z)
    q[3, 3] += parameters.offset_drift_m**2
    r = np.diag([parameters.com_noise_m**2, parameters.zmp_noise_m**2])
    p = scipy.linalg.solve_discrete_are(a_z.T, c_z.T, q, r)
    return np.asarray(p @ c_z.T @ np.linalg.inv(c_z @ p @ c_z.T + r))


class ObservedPreviewControl:
    """Preview control of both axes on the observed state (module docstring).

    Each period ``k``: correct the prior ``ẑ⁻_k`` with the measured CoM and ZMP, apply the
    preview law to the corrected state with the reference ``p^{ref} - d̂`` and the error sum
    of ``C_3 x̂ + d̂ - p^{ref}``, and predict ``ẑ⁻_{k+1}``, whose CoM is the next target.

    Args:
        gains: the preview gains of the cart table (:func:`compute_preview_gains`).
        zmp_reference_in_world: p^{ref} of every period [m], shape (N, 2); the preview
            window reads past the end as the last value.
        initial_state_in_world: rows x, y: CoM [m], velocity [m/s], acceleration [m/s²].
        parameters: the noise levels that set the observer's gain.
    """

    def __init__(
        self,
        gains: PreviewGains,
        zmp_reference_in_world: NDArray[np.float64],
        initial_state_in_world: NDArray[np.float64],
        parameters: ZmpObserverParameters | None = None,
    ) -> None:
        self.parameters = parameters or ZmpObserverParameters()
        p = gains.parameters
        self._a, self._b, self._c = observer_matrices(
            p.sampling_period_s, p.com_height_m, p.gravity_mps2
        )
        self.gain = observer_gain(
            self.parameters, p.sampling_period_s, p.com_height_m, p.gravity_mps2
        )
        self._gp = np.concatenate([[0.0], gains.preview_gains])
        self._g_i = float(gains.integral_gain)
        self._g_x = np.asarray(gains.state_gain, dtype=np.float64)
        self._reference = np.asarray(zmp_reference_in_world, dtype=np.float64)
        self._offsets = np.arange(self._gp.size)
        self.state = np.zeros((2, 4))
        """Prior of the next period, rows x, y: c [m], ċ [m/s], c̈ [m/s²], d [m]."""
        self.state[:, :3] = initial_state_in_world
        self._error_sum = np.zeros(2)
        self._y = np.zeros(2)
        self.jerk_in_world = np.zeros(2)
        """The jerk of the last period, (x, y) [m/s³]."""

    @property
    def offset_in_world(self) -> NDArray[np.float64]:
        """The estimated ZMP offset d̂ (x, y) [m], a view."""
        return self.state[:, 3]

    def update(
        self, k: int, com_in_world: NDArray[np.float64], zmp_in_world: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """One period: correct with the measurements of period ``k`` and predict ``k + 1``.

        Args:
            k: the period the measurements belong to [-].
            com_in_world: the measured CoM (x, y) [m].
            zmp_in_world: the measured ZMP (x, y) [m]; NaN (no contact) skips the correction.

        Returns:
            The CoM (x, y) of period ``k + 1`` [m], a view of the prediction.
        """
        n, limit = self._reference.shape[0], self.parameters.max_offset_m
        idx = np.minimum(k + self._offsets, n - 1)
        for axis in (0, 1):
            z = self.state[axis]
            if math.isfinite(float(zmp_in_world[axis])):
                self._y[0] = com_in_world[axis]
                self._y[1] = zmp_in_world[axis]
                z += self.gain @ (self._y - self._c @ z)
                z[3] = min(max(z[3], -limit), limit)
            window = self._reference[idx, axis]
            self._error_sum[axis] += float(self._c[1, :3] @ z[:3]) + z[3] - window[0]
            jerk = (
                -self._g_i * self._error_sum[axis]
                - float(self._g_x @ z[:3])
                - float(self._gp @ (window - z[3]))
            )
            z[:] = self._a @ z + self._b * jerk
            self.jerk_in_world[axis] = jerk
        return self.state[:, 0]
