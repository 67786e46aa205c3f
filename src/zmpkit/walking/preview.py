r"""Preview control of the cart-table model (Kajita et al., ICRA 2003).

On the cart-table model of :mod:`zmpkit.walking.cart_table` (state ``x = (c, c_dot,
c_ddot)`` [m, m/s, m/s^2], jerk input ``u`` [m/s^3], ZMP output ``p = C x`` [m]).

The controller minimises :math:`\sum_k Q_e e_k^2 + R \Delta u_k^2` with the tracking error
``e_k = p_k - p^{ref}_k`` on the augmented (error, state increment) system, whose discrete
algebraic Riccati solution ``P`` gives

.. math::

    u_k = -G_i \sum_{i=0}^{k} e_i - G_x x_k - \sum_{j=1}^{N_L} G_p(j)\, p^{ref}_{k+j}.

Paper B's walk uses the ZMP/IP controller of Urbann and Czarnetzki, an observer-based
preview controller on the same 3D-LIPM. Without sensor feedback (the pattern here) its
observer is idle and it plans the same kind of preview-optimal CoM; the observer belongs to
closed-loop stabilisation, not to this module.

The model's matrices and the gains are computed in :mod:`zmpkit.walking.cart_table` and
re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.cart_table import (
    PreviewGains,
    PreviewParameters,
    cart_table_matrices,
    compute_preview_gains,
)

__all__ = [
    "CoMTrajectory",
    "PreviewController",
    "PreviewGains",
    "PreviewParameters",
    "cart_table_matrices",
    "compute_preview_gains",
]

#: Block length of the scan that solves the closed loop in ``PreviewController.run`` [-].
SCAN_BLOCK = 32


def _read_only(array: NDArray[np.float64]) -> NDArray[np.float64]:
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class CoMTrajectory:
    """CoM motion planned by preview control, columns (x, y), world frame.

    Attributes:
        time_s: sample times [s], shape (N,).
        com_position_in_world: [m], shape (N, 2).
        com_velocity_in_world: [m/s], shape (N, 2).
        com_acceleration_in_world: [m/s^2], shape (N, 2).
        com_jerk_in_world: the input held over each period [m/s^3], shape (N, 2).
        zmp_in_world: cart-table ZMP ``c - (z_c/g) c_ddot`` [m], shape (N, 2).
        zmp_reference_in_world: the tracked reference [m], shape (N, 2).
        com_height_m: z_c [m].
    """

    time_s: NDArray[np.float64]
    com_position_in_world: NDArray[np.float64]
    com_velocity_in_world: NDArray[np.float64]
    com_acceleration_in_world: NDArray[np.float64]
    com_jerk_in_world: NDArray[np.float64]
    zmp_in_world: NDArray[np.float64]
    zmp_reference_in_world: NDArray[np.float64]
    com_height_m: float

    @property
    def zmp_error(self) -> NDArray[np.float64]:
        """Cart-table ZMP minus reference [m], shape (N, 2)."""
        return self.zmp_in_world - self.zmp_reference_in_world


class PreviewController:
    """Preview controller for both horizontal axes of the cart-table model.

    ``run`` plans a whole trajectory at once (vectorised); ``step`` advances one period in
    place, for use inside a control loop. Both implement the same control law.

    Args:
        gains: from :func:`compute_preview_gains`.
        initial_com_in_world: CoM (x, y) at rest at the start of ``step`` use [m].
    """

    def __init__(
        self, gains: PreviewGains, initial_com_in_world: tuple[float, float] = (0.0, 0.0)
    ) -> None:
        self.gains = gains
        p = gains.parameters
        self._A, self._B, self._C = cart_table_matrices(
            p.sampling_period_s, p.com_height_m, p.gravity_mps2
        )
        self._gp_padded = np.concatenate([[0.0], gains.preview_gains])  # weight 0 on p(k)
        self._state = np.zeros((2, 4))  # rows x, y: position, velocity, acceleration, sum e
        self._jerk = np.zeros(2)
        self._k_x = gains.integral_gain * self._C + gains.state_gain  # G_i C + G_x
        T = p.sampling_period_s
        g_x0, g_x1, g_x2 = (float(g) for g in gains.state_gain)
        integrator = (T, T * T / 2, T**3 / 6, -float(self._C[2]), gains.integral_gain)
        self._scalars = (*integrator, g_x0, g_x1, g_x2)
        closed = self._closed_loop_matrix()
        self._closed_powers = np.empty((SCAN_BLOCK + 1, 4, 4))  # M^0 .. M^b
        self._closed_powers[0] = np.eye(4)
        for i in range(SCAN_BLOCK):
            self._closed_powers[i + 1] = self._closed_powers[i] @ closed
        self.reset(initial_com_in_world)

    @property
    def window_length(self) -> int:
        """Length N_L + 1 of the reference window ``step`` takes [-]."""
        return self._gp_padded.size

    @property
    def state_in_world(self) -> NDArray[np.float64]:
        """Read-only view (2, 4) of the preview controller's state.

        Rows x, y; columns position [m], velocity [m/s], acceleration [m/s^2], sum of ZMP
        errors [m].
        """
        view = self._state.view()
        view.setflags(write=False)
        return view

    @property
    def last_jerk_in_world(self) -> NDArray[np.float64]:
        """Read-only view (2,) of the jerk applied by the last ``step`` [m/s^3]."""
        view = self._jerk.view()
        view.setflags(write=False)
        return view

    def reset(self, com_in_world: tuple[float, float]) -> None:
        """Put the CoM at rest at ``com_in_world`` [m] and clear the error sum."""
        self._state[:] = 0.0
        self._state[0, 0] = _validate.finite("com_in_world[0]", com_in_world[0])
        self._state[1, 0] = _validate.finite("com_in_world[1]", com_in_world[1])
        self._jerk[:] = 0.0

    def step(
        self, zmp_ref_x_window: NDArray[np.float64], zmp_ref_y_window: NDArray[np.float64]
    ) -> None:
        """Advance one period: from x(k) to x(k+1) with the jerk u(k); allocates no arrays.

        Args:
            zmp_ref_x_window: p_ref(k..k+N_L) along x [m], length ``window_length``.
            zmp_ref_y_window: the same along y [m].
        """
        if (
            len(zmp_ref_x_window) != self._gp_padded.size
            or len(zmp_ref_y_window) != self._gp_padded.size
        ):
            raise ParameterError(
                f"step windows must have length N_L + 1 = {self._gp_padded.size}, got "
                f"{len(zmp_ref_x_window)} and {len(zmp_ref_y_window)}"
            )
        self._advance_axis(0, zmp_ref_x_window)
        self._advance_axis(1, zmp_ref_y_window)

    def _advance_axis(self, axis: int, window: NDArray[np.float64]) -> None:
        """Kajita's law for one axis: reads x(k) and sum e(0..k-1), writes x(k+1), sum e(0..k)."""
        state, (t1, t2, t3, zc_over_g, g_i, g_x0, g_x1, g_x2) = self._state, self._scalars
        pos, vel, acc = state[axis, 0], state[axis, 1], state[axis, 2]
        error_sum = state[axis, 3] + pos - zc_over_g * acc - window[0]
        jerk = (
            -g_i * error_sum
            - (g_x0 * pos + g_x1 * vel + g_x2 * acc)
            - np.dot(self._gp_padded, window)
        )
        state[axis, 0] = pos + t1 * vel + t2 * acc + t3 * jerk
        state[axis, 1] = vel + t1 * acc + t2 * jerk
        state[axis, 2] = acc + t1 * jerk
        state[axis, 3] = error_sum
        self._jerk[axis] = jerk

    def _closed_loop_matrix(self) -> NDArray[np.float64]:
        """M of the closed loop ``z(k+1) = M z(k) + f(k+1)``, z = (x - p0 e_1, sum of past e)."""
        g = self.gains
        closed = np.zeros((4, 4))
        closed[:3, :3] = self._A - np.outer(self._B, self._k_x)
        closed[:3, 3] = -self._B * g.integral_gain
        closed[3, :3] = self._C
        closed[3, 3] = 1.0
        return closed

    def run(self, zmp_ref_x: NDArray[np.float64], zmp_ref_y: NDArray[np.float64]) -> CoMTrajectory:
        """Plan the CoM for a whole reference, starting at rest above its first sample.

        The reference is padded at the end with its last value for the preview. The
        internal ``step`` state is not used or changed. The closed loop is solved in
        deviation coordinates ``x - p_ref(0) e_1`` by a blocked scan, which performs the
        same recursion as ``step`` with numpy over blocks.

        Args:
            zmp_ref_x: reference x [m], shape (N,).
            zmp_ref_y: reference y [m], shape (N,).
        """
        ref = self._check_reference(zmp_ref_x, zmp_ref_y)
        g = self.gains
        p0 = ref[0].copy()
        ref_hat = ref - p0
        padded = np.concatenate([ref_hat[1:], np.repeat(ref_hat[-1:], g.preview_gains.size, 0)])
        preview = np.column_stack(
            [np.correlate(padded[:, a], g.preview_gains, mode="valid") for a in range(2)]
        )
        drive = g.integral_gain * ref_hat - preview - p0 * g.truncation_bias  # (N, 2)
        forcing = np.zeros((ref.shape[0], 4, 2))
        forcing[1:, :3] = self._B[None, :, None] * drive[:-1, None, :]
        forcing[1:, 3] = -ref_hat[:-1]
        z = _blocked_scan(self._closed_powers, forcing)  # (N, 4, 2)
        jerk = drive - np.einsum("i,nik->nk", self._k_x, z[:, :3]) - g.integral_gain * z[:, 3]
        position = z[:, 0] + p0
        zmp = position + self._C[2] * z[:, 2]
        time = np.arange(ref.shape[0], dtype=np.float64) * g.parameters.sampling_period_s
        arrays = (time, position, z[:, 1], z[:, 2], jerk, zmp, ref)
        time, position, velocity, acceleration, jerk, zmp, ref = (_read_only(a) for a in arrays)
        return CoMTrajectory(
            time, position, velocity, acceleration, jerk, zmp, ref, g.parameters.com_height_m
        )

    @staticmethod
    def _check_reference(
        zmp_ref_x: NDArray[np.float64], zmp_ref_y: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        x = _validate.finite_array("zmp_ref_x", zmp_ref_x, (None,))
        y = _validate.finite_array("zmp_ref_y", zmp_ref_y, (None,))
        if x.size == 0 or x.size != y.size:
            raise ParameterError(
                f"zmp_ref_x and zmp_ref_y must be non-empty and of equal length, got "
                f"{x.size} and {y.size}"
            )
        return np.column_stack([x, y])


def _blocked_scan(powers: NDArray[np.float64], forcing: NDArray[np.float64]) -> NDArray[np.float64]:
    """Solve ``z(k) = M z(k-1) + f(k)``, ``z(-1) = 0``, for all k with few numpy calls.

    Args:
        powers: ``M^0 .. M^b``, shape (b + 1, n, n), b the block length.
        forcing: f, shape (N, n, m) (m independent columns, e.g. the x and y axes).

    Returns:
        z, shape (N, n, m). Within each block of b samples the recursion runs for all
        blocks at once; then the block-end states are chained and propagated back in.
    """
    b = powers.shape[0] - 1
    n_samples, n, m = forcing.shape
    n_blocks = -(-n_samples // b)
    f = np.zeros((n_blocks * b, n, m))
    f[:n_samples] = forcing
    f = f.reshape(n_blocks, b, n, m)
    local = np.empty_like(f)  # the solution of each block from a zero state before it
    local[:, 0] = f[:, 0]
    for i in range(1, b):
        local[:, i] = powers[1] @ local[:, i - 1] + f[:, i]
    before = np.zeros((n_blocks, n, m))  # the state just before each block
    for j in range(1, n_blocks):
        before[j] = powers[b] @ before[j - 1] + local[j - 1, b - 1]
    z = local + np.einsum("iab,jbk->jiak", powers[1:], before)
    return z.reshape(n_blocks * b, n, m)[:n_samples]
