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
from zmpkit.walking.scalar_limits import clamp

__all__ = ["ObservedPreviewControl", "ZmpObserverParameters", "observer_gain", "observer_matrices"]

_AXES = (0, 1)


@dataclass(frozen=True)
class ZmpObserverParameters:
    """Noise levels that set the observer's gain (zmpkit's defaults; the paper gives none).

    The first defaults were chosen on four 10 s walks of the virtual robot (rigid; gears only;
    all effects at 0.2 and 0.25 m/s): the lowest mean trunk oscillation among the settings
    tried that stood in all four. The robustness sweep then showed that pushes were lost by a
    slow rebound, not by a capture point leaving the feet: with a fast offset (σ_d 0.5 mm per
    period) and the ZMP's innovation clipped at 3 cm, the offset absorbed what the pushed
    CoM should have shown. Two values were changed, chosen on eight all-effects walks pushed
    with 10 N at a quarter and three quarters of a step (4 of 8 fell; 1 with the new values):
    σ_d 0.5 → 0.1 mm and the clip 0.03 → 0.08 m. Judged on what they were not chosen on
    (all effects, seed 0, the sweep's cases): 10 N pushes at the other phases 1/8 → 1/8
    falls, 20 N pushes 13/16 → 8/16, the 20 unpushed cases (speeds, step durations,
    sideways, turning, sensor faults) 0 → 0 falls with the 2 Hz trunk amplitude lower in 16
    of 20 (0.030 → 0.026 rad at 0.2 m/s; the others within 0.6 mrad) and speed errors
    within 1.4 points of the old ones;
    MoToFlex's own servo gains now walk (−12 % speed). Trusting the kinematic CoM less as
    well (σ_c 0.1 m) lost 6 of the 32 pushes instead of 10, but made the robot's yaw slip:
    the straight 0.3 m/s walk's heading error 0.039 → 0.085 rad, the rigid robot's 2 Hz
    amplitude 0.006 → 0.015 rad; not kept.

    Attributes:
        com_noise_m: σ_c, error of the kinematic CoM estimate [m].
        zmp_noise_m: σ_p, error of the measured ZMP against the cart table [m].
        jerk_noise_mps3: σ_u, unmodelled CoM jerk per period [m/s³].
        offset_drift_m: σ_d, change of the ZMP offset per period [m].
        max_offset_m: the estimated offset is clamped to ±this [m].
        max_zmp_innovation_m: a measured ZMP further than this from the observer's prediction
            counts as this far (a robust correction: a foot rocking heel to toe, a spike,
            must not throw the CoM plan) [m].
    """

    com_noise_m: float = 0.03
    zmp_noise_m: float = 0.03
    jerk_noise_mps3: float = 0.5
    offset_drift_m: float = 0.0001
    max_offset_m: float = 0.03
    max_zmp_innovation_m: float = 0.08

    def __post_init__(self) -> None:
        for name in ("com_noise_m", "zmp_noise_m", "jerk_noise_mps3", "offset_drift_m"):
            _validate.positive(f"ZmpObserverParameters.{name}", getattr(self, name))
        _validate.positive("ZmpObserverParameters.max_offset_m", self.max_offset_m, "m")
        _validate.positive(
            "ZmpObserverParameters.max_zmp_innovation_m", self.max_zmp_innovation_m, "m"
        )


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
        self._gp_sum = float(self._gp.sum())
        self._g_i = float(gains.integral_gain)
        self._g_x = [float(g) for g in gains.state_gain]
        reference = np.asarray(zmp_reference_in_world, dtype=np.float64)
        self._n, size = reference.shape[0], self._gp.size
        self._last = self._n - 1  # the last period with a reference [-]
        self._l = self.gain.tolist()
        self._a3 = self._a[:3, :3].tolist()
        self._b3 = self._b[:3].tolist()
        self._zc_over_g = -float(self._c[1, 2])
        self.state = np.zeros((2, 4))
        """Prior of the next period, rows x, y: c [m], ċ [m/s], c̈ [m/s²], d [m]."""
        self.state[:, :3] = initial_state_in_world
        self._error_sum = np.zeros(2)
        self.jerk_in_world = np.zeros(2)
        """The jerk of the last period, (x, y) [m/s³]."""
        self._init_buffers(reference, size)

    def _init_buffers(self, reference: NDArray[np.float64], size: int) -> None:
        """The arrays and views a period writes and reads, made once (a period makes none)."""
        padded = self._n + size  # padded with the last value
        self._reference_xy = np.empty((2, padded))
        self._reference_xy[:, : self._n] = reference.T
        self._reference_xy[:, self._n :] = reference[-1:].T
        self._reference = [self._reference_xy[0], self._reference_xy[1]]
        self._reference_flat = self._reference_xy.reshape(-1)
        self._window_first = np.zeros((), dtype=np.intp)  # k
        rows = np.array([[0], [padded]], dtype=np.intp)  # where x and y start in the flat array
        self._window_offsets = rows + np.arange(size, dtype=np.intp)
        self._window_index = np.empty((2, size), dtype=np.intp)
        self._window = np.empty((2, size))  # p^ref_{k..k+size-1}, rows x, y
        self._preview = np.zeros(2)  # Σ G_p(j) p^ref_{k+j}, x and y
        self._window_rows = [self._window[0:1], self._window[1:2]]
        self._preview_rows = [self._preview[0:1], self._preview[1:2]]
        self._state_rows = [self.state[0], self.state[1]]
        self._next_com = self.state[:, 0]
        self._offset = self.state[:, 3]

    @property
    def reference_by_axis(self) -> list[NDArray[np.float64]]:
        """p^{ref} of every period, one writable array per axis (x, y) [m].

        Padded past the walk's end with its last value. A compensation that adapts the
        reference online (paper B's Algorithm 2) writes the periods still to come here.
        """
        return self._reference

    @property
    def offset_in_world(self) -> NDArray[np.float64]:
        """The estimated ZMP offset d̂ (x, y) [m], a view (the same one every time)."""
        return self._offset

    def model_zmp(self, axis: int) -> float:
        r"""The ZMP of the current state along ``axis`` (0: x, 1: y) [m].

        :math:`c - (z_c/g)\,\ddot c + \hat d`: the cart table's ZMP with the estimated
        offset; after :meth:`update`, the ZMP the controller asks for at period ``k + 1``.
        """
        z = self._state_rows[axis]
        return z.item(0) - self._zc_over_g * z.item(2) + z.item(3)

    def update(
        self, k: int, com_in_world: NDArray[np.float64], zmp_in_world: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """One period: correct with the measurements of period ``k`` and predict ``k + 1``.

        Real-time code: it creates no numpy array, view or scalar (the preview window of both
        axes is gathered into a buffer, every view is made at construction) and keeps nothing
        (``tests/walking/test_tick_allocations.py``).

        Args:
            k: the period the measurements belong to [-].
            com_in_world: the measured CoM (x, y) [m].
            zmp_in_world: the measured ZMP (x, y) [m]; NaN (no contact) skips the correction.

        Returns:
            The CoM (x, y) of period ``k + 1`` [m], a view of the prediction.
        """
        limit, k = self.parameters.max_offset_m, min(k, self._last)
        clip = self.parameters.max_zmp_innovation_m
        l_gain, g_x, zc_g = self._l, self._g_x, self._zc_over_g
        (a00, a01, a02), (_, a11, a12), (_, _, a22) = self._a3
        b0, b1, b2 = self._b3
        self._read_window(k)
        for axis in _AXES:
            z = self._state_rows[axis]
            c, v, a, d = z.item(0), z.item(1), z.item(2), z.item(3)
            zmp = zmp_in_world.item(axis)
            if math.isfinite(zmp):
                e_c = com_in_world.item(axis) - c
                e_p = zmp - (c - zc_g * a + d)
                e_p = clamp(e_p, clip)
                c += l_gain[0][0] * e_c + l_gain[0][1] * e_p
                v += l_gain[1][0] * e_c + l_gain[1][1] * e_p
                a += l_gain[2][0] * e_c + l_gain[2][1] * e_p
                d += l_gain[3][0] * e_c + l_gain[3][1] * e_p
                d = clamp(d, limit)
            # Σ G_p(j) p^ref_{k+j}: a (1, n)·(n,) product is numpy's dot of two vectors
            np.dot(self._window_rows[axis], self._gp, out=self._preview_rows[axis])
            reference_k = self._reference_xy.item(axis, k)
            error_sum = self._error_sum.item(axis) + (c - zc_g * a + d - reference_k)
            self._error_sum[axis] = error_sum
            jerk = (
                -self._g_i * error_sum
                - (g_x[0] * c + g_x[1] * v + g_x[2] * a)
                - (self._preview.item(axis) - d * self._gp_sum)
            )
            z[0] = a00 * c + a01 * v + a02 * a + b0 * jerk
            z[1] = a11 * v + a12 * a + b1 * jerk
            z[2] = a22 * a + b2 * jerk
            z[3] = d
            self.jerk_in_world[axis] = jerk
        return self._next_com

    def _read_window(self, k: int) -> None:
        """Copy p^ref of periods ``k .. k + size - 1`` of both axes into the window buffer."""
        self._window_first[()] = k
        np.add(self._window_offsets, self._window_first, out=self._window_index)
        # k <= N - 1 keeps every index in range; mode 'raise' would copy the window first
        self._reference_flat.take(self._window_index, out=self._window, mode="clip")
