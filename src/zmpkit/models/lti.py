r"""Linear time-invariant systems in state-space form, continuous and discrete.

A continuous system

.. math::

    \dot{x} = A x + B u, \qquad y = C x + D u

is turned into the discrete system of a controller loop by an exact zero-order hold
(the input is held constant over each sample period :math:`\Delta t`):

.. math::

    A_d = e^{A \Delta t}, \qquad B_d = \int_0^{\Delta t} e^{A \tau} \, d\tau \; B,

both read off one matrix exponential of the augmented block matrix
:math:`\begin{bmatrix} A & B \\ 0 & 0 \end{bmatrix} \Delta t`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm

from zmpkit._validate import finite_array, positive
from zmpkit.errors import ParameterError

__all__ = ["DiscreteLinearSystem", "DiscreteSimulation", "LinearSystem", "zero_order_hold"]

if TYPE_CHECKING:  # python-control pulls in matplotlib: import it only when used
    import control

FloatArray = NDArray[np.float64]


def _state_space_matrices(
    names: tuple[str, str, str, str], A: ArrayLike, B: ArrayLike, C: ArrayLike, D: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Validate (A, B, C, D): finite, 2-D, shapes (n, n), (n, m), (p, n), (p, m), n, m, p >= 1."""
    a = finite_array(names[0], A, (None, None))
    n = a.shape[0]
    if n < 1 or a.shape != (n, n):
        raise ParameterError(f"{names[0]} must be square (n, n) with n >= 1, got shape {a.shape}")
    b = finite_array(names[1], B, (n, None))
    c = finite_array(names[2], C, (None, n))
    if b.shape[1] < 1 or c.shape[0] < 1:
        raise ParameterError(
            f"{names[1]} and {names[2]} need at least one input and one output, "
            f"got shapes {b.shape} and {c.shape}"
        )
    d = finite_array(names[3], D, (c.shape[0], b.shape[1]))
    matrices = (a, b, c, d)
    for matrix in matrices:
        matrix.setflags(write=False)
    return matrices


def _increasing_times(name: str, t: ArrayLike, min_samples: int = 2) -> FloatArray:
    """Return ``t`` [s] as a 1-D float array, finite and strictly increasing."""
    times = finite_array(name, t, (None,))
    if times.size < min_samples:
        raise ParameterError(f"{name} needs at least {min_samples} samples, got {times.size}")
    steps = np.diff(times)
    if np.any(steps <= 0.0):
        k = int(np.argmax(steps <= 0.0))
        raise ParameterError(
            f"{name} must be strictly increasing, but {name}[{k + 1}] = {times[k + 1]} "
            f"<= {name}[{k}] = {times[k]}"
        )
    return times


def zero_order_hold(A: ArrayLike, B: ArrayLike, dt: float) -> tuple[FloatArray, FloatArray]:
    r"""Exact zero-order-hold discretisation of :math:`\dot{x} = A x + B u`.

    Args:
        A: state matrix, shape (n, n) [1/s].
        B: input matrix, shape (n, m).
        dt: sample period [s].

    Returns:
        ``(Ad, Bd)`` with :math:`A_d = e^{A dt}` and :math:`B_d = \int_0^{dt} e^{A\tau}d\tau B`.
    """
    a = np.asarray(A, dtype=np.float64)
    b = np.asarray(B, dtype=np.float64)
    n, m = b.shape
    augmented = np.zeros((n + m, n + m))
    augmented[:n, :n] = a
    augmented[:n, n:] = b
    phi = expm(augmented * positive("dt", dt, "s"))
    return phi[:n, :n], phi[:n, n:]


@dataclass(frozen=True, eq=False)
class LinearSystem:
    r"""Continuous LTI system :math:`\dot{x} = A x + B u,\; y = C x + D u`.

    Attributes:
        A: state matrix, shape (n, n) [1/s].
        B: input matrix, shape (n, m).
        C: output matrix, shape (p, n).
        D: feed-through matrix, shape (p, m).

    Units of the entries follow the states, inputs and outputs of the model that built it.
    The stored arrays are float64 and read-only.
    """

    A: FloatArray
    B: FloatArray
    C: FloatArray
    D: FloatArray

    def __init__(self, A: ArrayLike, B: ArrayLike, C: ArrayLike, D: ArrayLike) -> None:
        # Written out (the dataclass keeps it) so that the matrices may be given as any
        # array-like; they are stored as validated, read-only float64 arrays.
        matrices = _state_space_matrices(("A", "B", "C", "D"), A, B, C, D)
        for name, matrix in zip("ABCD", matrices, strict=True):
            object.__setattr__(self, name, matrix)

    @property
    def n_states(self) -> int:
        """Number of states n."""
        return int(self.A.shape[0])

    @property
    def n_inputs(self) -> int:
        """Number of inputs m."""
        return int(self.B.shape[1])

    @property
    def n_outputs(self) -> int:
        """Number of outputs p."""
        return int(self.C.shape[0])

    def poles(self) -> NDArray[np.complex128]:
        """Eigenvalues of A [1/s]."""
        return np.linalg.eigvals(self.A).astype(np.complex128)

    def to_control(self) -> control.StateSpace:
        """The same system as a continuous :class:`control.StateSpace`."""
        import control

        return control.ss(self.A, self.B, self.C, self.D)

    def discretize(self, dt: float) -> DiscreteLinearSystem:
        """Exact zero-order-hold discretisation with sample period ``dt`` [s]."""
        Ad, Bd = zero_order_hold(self.A, self.B, dt)
        return DiscreteLinearSystem(Ad, Bd, self.C, self.D, dt)


class DiscreteSimulation(NamedTuple):
    """States and outputs of :meth:`DiscreteLinearSystem.simulate`.

    Attributes:
        x: states x[0] … x[N], shape (N + 1, n).
        y: outputs y[0] … y[N-1], shape (N, p), with y[k] = C x[k] + D u[k].
    """

    x: FloatArray
    y: FloatArray


@dataclass(frozen=True, eq=False)
class DiscreteLinearSystem:
    r"""Discrete LTI system :math:`x_{k+1} = A_d x_k + B_d u_k,\; y_k = C x_k + D u_k`.

    Attributes:
        Ad: state transition matrix, shape (n, n).
        Bd: input matrix, shape (n, m).
        C: output matrix, shape (p, n).
        D: feed-through matrix, shape (p, m).
        dt: sample period [s].
    """

    Ad: FloatArray
    Bd: FloatArray
    C: FloatArray
    D: FloatArray
    dt: float

    def __post_init__(self) -> None:
        names = ("Ad", "Bd", "C", "D")
        matrices = _state_space_matrices(names, self.Ad, self.Bd, self.C, self.D)
        for name, matrix in zip(names, matrices, strict=True):
            object.__setattr__(self, name, matrix)
        object.__setattr__(self, "dt", positive("dt", self.dt, "s"))

    def to_control(self) -> control.StateSpace:
        """The same system as a discrete :class:`control.StateSpace` with period ``dt``."""
        import control

        return control.ss(self.Ad, self.Bd, self.C, self.D, self.dt)

    def simulate(self, u: ArrayLike, x0: ArrayLike | None = None) -> DiscreteSimulation:
        """Run the difference equation from ``x0`` over the input sequence ``u``.

        Args:
            u: inputs, shape (N,) for a single-input system or (N, m).
            x0: initial state, shape (n,); zeros when omitted.

        Returns:
            The states, shape (N + 1, n), and outputs, shape (N, p).
        """
        n, m = self.Bd.shape
        inputs = finite_array("u", u)
        if inputs.ndim == 1 and m == 1:
            inputs = inputs[:, np.newaxis]
        if inputs.ndim != 2 or inputs.shape[1] != m:
            expected = "(N,) or (N, 1)" if m == 1 else f"(N, {m})"
            raise ParameterError(f"u must have shape {expected}, got shape {inputs.shape}")
        x = np.empty((inputs.shape[0] + 1, n))
        x[0] = np.zeros(n) if x0 is None else finite_array("x0", x0, (n,))
        for k, u_k in enumerate(inputs):
            x[k + 1] = self.Ad @ x[k] + self.Bd @ u_k
        y = x[:-1] @ self.C.T + inputs @ self.D.T
        return DiscreteSimulation(x=x, y=y)
