r"""Cart-table model and its optimal preview gains (Kajita et al., ICRA 2003).

The cart-table model is the 3D-LIPM written with the CoM jerk as input, one copy per
horizontal axis. Discrete state ``x = (c, c_dot, c_ddot)`` [m, m/s, m/s^2], input the jerk
``u`` [m/s^3], held constant over a period ``T`` [s]; output the ZMP ``p`` [m]:

.. math::

    x_{k+1} = A x_k + B u_k, \quad p_k = C x_k, \quad
    A = \begin{bmatrix}1 & T & T^2/2\\ 0 & 1 & T\\ 0 & 0 & 1\end{bmatrix},\;
    B = \begin{bmatrix}T^3/6\\ T^2/2\\ T\end{bmatrix},\;
    C = \begin{bmatrix}1 & 0 & -z_c/g\end{bmatrix}.

The gains minimise :math:`\sum_k Q_e e_k^2 + R \Delta u_k^2` with the tracking error
``e_k = p_k - p^{ref}_k`` on the augmented (error, state increment) system; they come from
its discrete algebraic Riccati solution ``P``. The controller that applies them is
:class:`zmpkit.walking.preview.PreviewController`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2

__all__ = [
    "PreviewGains",
    "PreviewParameters",
    "cart_table_matrices",
    "compute_preview_gains",
]


@dataclass(frozen=True)
class PreviewParameters:
    """Cart-table model and cost weights.

    Attributes:
        sampling_period_s: control period T [s] (paper B: 0.01 s).
        com_height_m: constant CoM height z_c above the ground [m] (paper B's walk: 0.26 m).
        horizon_s: preview horizon [s]; N_L = round(horizon_s / T) samples.
        error_weight: Q_e, weight on the squared ZMP error [1/m^2].
        jerk_weight: R, weight on the squared jerk increment [s^6/m^2].
        gravity_mps2: g [m/s^2].
    """

    sampling_period_s: float = 0.01
    com_height_m: float = 0.26
    horizon_s: float = 1.6
    error_weight: float = 1.0
    jerk_weight: float = 1e-6
    gravity_mps2: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        _validate.positive("PreviewParameters.sampling_period_s", self.sampling_period_s, "s")
        _validate.positive("PreviewParameters.com_height_m", self.com_height_m, "m")
        _validate.positive("PreviewParameters.error_weight", self.error_weight)
        _validate.positive("PreviewParameters.jerk_weight", self.jerk_weight)
        _validate.positive("PreviewParameters.gravity_mps2", self.gravity_mps2, "m/s^2")
        horizon = _validate.positive("PreviewParameters.horizon_s", self.horizon_s, "s")
        if round(horizon / self.sampling_period_s) < 1:
            raise ParameterError(
                f"PreviewParameters.horizon_s must span at least one period "
                f"({self.sampling_period_s} s), got {horizon} s"
            )

    @property
    def preview_steps(self) -> int:
        """N_L, the number of future reference samples used [-]."""
        return round(self.horizon_s / self.sampling_period_s)


def cart_table_matrices(
    sampling_period_s: float, com_height_m: float, gravity_mps2: float = STANDARD_GRAVITY_MPS2
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Exact discrete cart-table matrices A (3, 3), B (3,), C (3,) for a jerk held over T."""
    T = sampling_period_s
    A = np.array([[1.0, T, T * T / 2], [0.0, 1.0, T], [0.0, 0.0, 1.0]])
    B = np.array([T**3 / 6, T * T / 2, T])
    C = np.array([1.0, 0.0, -com_height_m / gravity_mps2])
    return A, B, C


def _read_only(array: NDArray[np.float64]) -> NDArray[np.float64]:
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class PreviewGains:
    """Optimal preview gains and the Riccati solution they come from.

    Attributes:
        parameters: the model and weights.
        integral_gain: G_i [1/s^3] (acts on the sum of ZMP errors [m]).
        state_gain: G_x, shape (3,) [1/s^3, 1/s^2, 1/s].
        preview_gains: G_p(j), j = 1..N_L, shape (N_L,) [1/s^3].
        riccati_solution: P of the augmented 4-state system, shape (4, 4).
        augmented_a: the augmented A~, shape (4, 4).
        augmented_b: the augmented B~, shape (4,).
    """

    parameters: PreviewParameters
    integral_gain: float
    state_gain: NDArray[np.float64]
    preview_gains: NDArray[np.float64]
    riccati_solution: NDArray[np.float64]
    augmented_a: NDArray[np.float64]
    augmented_b: NDArray[np.float64]

    @property
    def truncation_bias(self) -> float:
        """``G_x[0] + sum_j G_p(j)`` [-]: 0 for an infinite horizon.

        The control law is translation-invariant only up to this term: a reference shifted by
        ``d`` [m] adds a constant jerk ``-d * truncation_bias`` that the integral term then
        removes. A horizon long enough for the preview gains to decay keeps it small.
        """
        return float(self.state_gain[0] + self.preview_gains.sum())

    @property
    def augmented_q(self) -> NDArray[np.float64]:
        """Q~ = diag(Q_e, 0, 0, 0) of the augmented system."""
        return np.diag([self.parameters.error_weight, 0.0, 0.0, 0.0])


def compute_preview_gains(parameters: PreviewParameters) -> PreviewGains:
    """Solve the DARE of the augmented system and derive G_i, G_x and G_p(1..N_L).

    Augmented state ``(e_k, x_k - x_{k-1})``, input ``u_k - u_{k-1}`` (Katayama 1985, as
    used by Kajita 2003): ``A~ = [[1, C A], [0, A]]``, ``B~ = [C B; B]``,
    ``Q~ = diag(Q_e, 0, 0, 0)``. With ``s = 1 / (R + B~' P B~)``: ``G_i = s B~' P I~``,
    ``G_x = s B~' P F~``, ``G_p(1) = -G_i``, ``G_p(j) = s B~' X(j-1)`` with
    ``X(1) = -A_c' P I~``, ``X(j) = A_c' X(j-1)``, ``A_c = A~ - B~ s B~' P A~``,
    ``I~ = e_1``, ``F~ = [C A; A]``.
    """
    p = parameters
    A, B, C = cart_table_matrices(p.sampling_period_s, p.com_height_m, p.gravity_mps2)
    a_aug = np.zeros((4, 4))
    a_aug[0, 0] = 1.0
    a_aug[0, 1:] = C @ A
    a_aug[1:, 1:] = A
    b_aug = np.concatenate([[C @ B], B])
    q_aug = np.diag([p.error_weight, 0.0, 0.0, 0.0])
    P = scipy.linalg.solve_discrete_are(a_aug, b_aug[:, None], q_aug, np.array([[p.jerk_weight]]))
    scale = 1.0 / (p.jerk_weight + b_aug @ P @ b_aug)
    integral_gain = scale * (b_aug @ P[:, 0])  # I~ = e_1
    state_gain = scale * (b_aug @ P @ a_aug[:, 1:])  # F~ = A~[:, 1:]
    a_closed = a_aug - np.outer(b_aug, scale * (b_aug @ P @ a_aug))
    preview = np.empty(p.preview_steps)
    preview[0] = -integral_gain
    x_tilde = -a_closed.T @ P[:, 0]
    for j in range(1, p.preview_steps):
        preview[j] = scale * (b_aug @ x_tilde)
        x_tilde = a_closed.T @ x_tilde
    return PreviewGains(
        p,
        float(integral_gain),
        _read_only(state_gain),
        _read_only(preview),
        _read_only(P),
        _read_only(a_aug),
        _read_only(b_aug),
    )
