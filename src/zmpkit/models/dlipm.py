r"""Dynamic LIPM (DLIPM, paper A §4.2): the LIPM plus an ankle spring k_a and damper B_a.

With the mass kept explicit (paper A, eq. 8–10), the ankle angle :math:`\theta` [rad]
answers a ZMP reference :math:`x_{ref}` [m] as

.. math::

    m l^2 \ddot\theta + B_a l \dot\theta + (k_a - m g) l \theta = m g \, x_{ref}

    \frac{\Theta(s)}{X(s)} = \frac{\gamma}{s^2 + \alpha s + \beta}, \quad
    \gamma = \frac{g}{l^2}, \quad \alpha = \frac{B_a}{m l}, \quad
    \beta = \frac{k_a - m g}{m l}, \quad K_{DC} = \frac{\gamma}{\beta}

with :math:`k_a` in [N] (its torque is :math:`k_a l \theta`) and :math:`B_a` in [N·s].
Setting :math:`k_a = B_a = 0` gives the LIPM, :math:`\beta = -g/l`: unstable.

Units in paper A. Its eq. 11 writes :math:`\beta = (k_a - g)/l`, i.e. k_a per unit mass
[N/kg = m/s²], while :math:`\alpha = B_a/(m l)` keeps the mass (B_a in N·s); see
:meth:`Dlipm.from_per_unit_mass` and :attr:`Dlipm.k_a_per_kg`. Its design example (§4.4,
:math:`\zeta = 0.8`, :math:`\omega_n = 0.4376`) is the DLIPM whose DC gain equals the LIPM's
:math:`1/l` with the angle in *degrees* (the paper's code sends :math:`\theta` to the joint
in degrees): :math:`\gamma/\beta = (180/\pi)/l` gives
:math:`\omega_n = \sqrt{(g/l)\,\pi/180}` = 0.4379 rad/s for g = 9.81 m/s², l = 0.893 m
(0.4376 with g = 9.8), see :func:`paper_units_omega_n`. In SI radians the same
DC-gain-matching design has :math:`\omega_n = \sqrt{g/l}` = 3.314 rad/s for l = 0.893 m.
"The LIPM's 1/l" is a magnitude: with the sign of paper A's eq. 9 the LIPM limit has the
formal DC gain :math:`\gamma/\beta = -1/l`. The paper calls :math:`\zeta = 0.8` over-damped;
it is under-damped (1.5 % overshoot).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import expm

from zmpkit._validate import finite, non_negative, positive
from zmpkit.errors import ModelError, ParameterError
from zmpkit.models.lti import DiscreteLinearSystem, LinearSystem, _increasing_times
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2

__all__ = ["Dlipm", "DlipmStepResponse", "paper_units_omega_n"]

if TYPE_CHECKING:  # python-control pulls in matplotlib: import it only when used
    import control

FloatArray = NDArray[np.float64]


def paper_units_omega_n(length: float, g: float = STANDARD_GRAVITY_MPS2) -> float:
    r"""Paper A's design :math:`\omega_n = \sqrt{(g/l)\,\pi/180}` [1/s] (see module note).

    It is the natural frequency of the DLIPM whose DC gain is :math:`(180/\pi)/l`, the
    LIPM's :math:`1/l` with :math:`\theta` in degrees.

    Args:
        length: pendulum length, ankle to CoM [m].
        g: gravitational acceleration [m/s²].
    """
    return math.sqrt(positive("g", g, "m/s^2") / positive("length", length, "m") * math.pi / 180)


@dataclass(frozen=True, eq=False)
class DlipmStepResponse:
    """Exact response of a DLIPM at rest to a ZMP-reference step at t = 0.

    Attributes:
        t: sample times [s], shape (N,).
        theta: ankle angle [rad], shape (N,).
        theta_dot: ankle angular velocity [rad/s], shape (N,).
        amplitude_m: step size of :math:`x_{ref}` [m].
    """

    t: FloatArray
    theta: FloatArray
    theta_dot: FloatArray
    amplitude_m: float


@dataclass(frozen=True)
class Dlipm:
    r"""Dynamic LIPM with SI parameters and explicit mass (module docstring).

    Attributes:
        mass: pendulum mass at the CoM [kg].
        length: pendulum length, ankle to CoM [m].
        k_a: ankle spring constant [N]; its torque is :math:`k_a l \theta` [N·m].
        b_a: ankle damper constant [N·s]; its torque is :math:`B_a l \dot\theta` [N·m].
        g: gravitational acceleration [m/s²].
    """

    mass: float
    length: float
    k_a: float
    b_a: float
    g: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", positive("mass", self.mass, "kg"))
        object.__setattr__(self, "length", positive("length", self.length, "m"))
        object.__setattr__(self, "k_a", finite("k_a", self.k_a))
        object.__setattr__(self, "b_a", finite("b_a", self.b_a))
        object.__setattr__(self, "g", positive("g", self.g, "m/s^2"))

    @classmethod
    def lipm(cls, mass: float, length: float, g: float = STANDARD_GRAVITY_MPS2) -> Dlipm:
        r"""The plain LIPM, :math:`k_a = B_a = 0`, :math:`\beta = -g/l` (unstable)."""
        return cls(mass, length, 0.0, 0.0, g)

    @classmethod
    def design(
        cls,
        mass: float,
        length: float,
        *,
        dc_gain: float,
        zeta: float,
        g: float = STANDARD_GRAVITY_MPS2,
    ) -> Dlipm:
        r"""The DLIPM with DC gain ``dc_gain`` [rad/m] and damping ratio ``zeta`` [-].

        :math:`\beta = \gamma / K_{DC}`, :math:`\alpha = 2\zeta\sqrt\beta`, then
        :math:`k_a = m l \beta + m g` and :math:`B_a = m l \alpha`.

        Raises:
            ParameterError: if ``dc_gain`` <= 0 (no stable DLIPM has it) or ``zeta`` < 0.
        """
        gain = positive("dc_gain", dc_gain, "rad/m")
        damping = non_negative("zeta", zeta)
        m, g_ = positive("mass", mass, "kg"), positive("g", g, "m/s^2")
        length_m = positive("length", length, "m")
        beta = g_ / length_m**2 / gain
        alpha = 2.0 * damping * math.sqrt(beta)
        return cls(m, length_m, k_a=m * length_m * beta + m * g_, b_a=m * length_m * alpha, g=g_)

    @classmethod
    def from_per_unit_mass(
        cls,
        mass: float,
        length: float,
        k_a_per_kg: float,
        b_a: float,
        g: float = STANDARD_GRAVITY_MPS2,
    ) -> Dlipm:
        r"""Build from paper A's units, k_a per unit mass: :math:`\beta = (k_a' - g)/l`.

        The inverse is :attr:`k_a_per_kg` (with :attr:`b_a` unchanged).

        Args:
            mass: pendulum mass [kg].
            length: pendulum length [m].
            k_a_per_kg: the paper's spring constant :math:`k_a' = k_a/m` [N/kg = m/s²].
            b_a: the damper constant [N·s]; the paper keeps the mass in α, so it is
                already in SI and is taken as is.
            g: gravitational acceleration [m/s²].
        """
        m = positive("mass", mass, "kg")
        return cls(m, length, k_a=m * finite("k_a_per_kg", k_a_per_kg), b_a=b_a, g=g)

    @property
    def k_a_per_kg(self) -> float:
        """Spring constant per unit mass, :math:`k_a/m` [N/kg], as paper A's β uses it."""
        return self.k_a / self.mass

    @property
    def gamma(self) -> float:
        r""":math:`\gamma = g / l^2` [rad/(m·s²)]."""
        return self.g / self.length**2

    @property
    def alpha(self) -> float:
        r""":math:`\alpha = B_a / (m l)` [1/s]."""
        return self.b_a / (self.mass * self.length)

    @property
    def beta(self) -> float:
        r""":math:`\beta = (k_a - m g) / (m l)` [1/s²]."""
        return (self.k_a - self.mass * self.g) / (self.mass * self.length)

    @property
    def dc_gain(self) -> float:
        r"""DC gain :math:`\gamma/\beta` [rad/m] (eq. 12).

        Raises:
            ModelError: if :math:`\beta = 0` (a pole at s = 0).
        """
        if self.beta == 0.0:
            raise ModelError(
                f"the DC gain gamma/beta is undefined: beta = 0 because k_a = m·g = "
                f"{self.k_a:.6g} N, which puts a pole at s = 0"
            )
        return self.gamma / self.beta

    @property
    def omega_n(self) -> float:
        r"""Natural frequency :math:`\omega_n = \sqrt\beta` [rad/s].

        Raises:
            ModelError: if :math:`\beta \le 0`.
        """
        if self.beta <= 0.0:
            raise ModelError(
                f"omega_n = sqrt(beta) needs beta > 0, got beta = {self.beta:.6g} 1/s^2 "
                f"(k_a = {self.k_a:.6g} N, m·g = {self.mass * self.g:.6g} N)"
            )
        return math.sqrt(self.beta)

    @property
    def zeta(self) -> float:
        r"""Damping ratio :math:`\zeta = \alpha / (2\omega_n)` [-]; ModelError if β <= 0."""
        return self.alpha / (2.0 * self.omega_n)

    @property
    def is_stable(self) -> bool:
        r"""Whether both poles lie in the open left half-plane: :math:`\alpha > 0, \beta > 0`."""
        return self.alpha > 0.0 and self.beta > 0.0

    def require_stable(self) -> Dlipm:
        """Return ``self`` if :attr:`is_stable`.

        Raises:
            ModelError: naming β (or α), its value and the bound k_a (or B_a) must pass.
        """
        if self.beta <= 0.0:
            raise ModelError(
                f"the DLIPM is unstable: beta = (k_a - m·g)/(m·l) = {self.beta:.6g} 1/s^2 <= 0; "
                f"k_a must exceed m·g = {self.mass * self.g:.6g} N, got k_a = {self.k_a:.6g} N"
            )
        if self.alpha <= 0.0:
            raise ModelError(
                f"the DLIPM is not asymptotically stable: alpha = B_a/(m·l) = "
                f"{self.alpha:.6g} 1/s <= 0; B_a must be > 0 N·s, got B_a = {self.b_a:.6g} N·s"
            )
        return self

    def transfer_function(self) -> control.TransferFunction:
        r""":math:`\Theta(s)/X(s) = \gamma/(s^2 + \alpha s + \beta)`, input [m], output [rad]."""
        import control

        return control.tf([self.gamma], [1.0, self.alpha, self.beta])

    def state_space(self) -> LinearSystem:
        """State (θ [rad], θ̇ [rad/s]), input x_ref [m], output θ [rad]."""
        A = [[0.0, 1.0], [-self.beta, -self.alpha]]
        return LinearSystem(A, [[0.0], [self.gamma]], [[1.0, 0.0]], [[0.0]])

    def discretize(self, dt: float) -> DiscreteLinearSystem:
        """Exact zero-order-hold discretisation with sample period ``dt`` [s]."""
        return self.state_space().discretize(dt)

    def step_response(self, t: ArrayLike, amplitude_m: float) -> DlipmStepResponse:
        """Exact response at rest to :math:`x_{ref}(t) = ` ``amplitude_m`` [m] for t >= 0.

        Exact at any sample times (one matrix exponential per distinct sample interval).

        Args:
            t: sample times [s], strictly increasing, ``t[0] >= 0``.
            amplitude_m: step size of the ZMP reference [m].
        """
        times = _increasing_times("t", t, min_samples=1)
        if times[0] < 0.0:
            raise ParameterError(f"t must start at or after the step at t = 0 s, got {times[0]} s")
        amplitude = finite("amplitude_m", amplitude_m)
        states = _constant_input_states(self.state_space(), times, amplitude)
        return DlipmStepResponse(times, states[:, 0], states[:, 1], amplitude)


def _constant_input_states(system: LinearSystem, times: FloatArray, u: float) -> FloatArray:
    """States at ``times`` [s] of a system at rest at t = 0 under the constant input ``u``."""
    n = system.n_states
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n] = system.A
    augmented[:n, n:] = system.B
    z = np.zeros(n + 1)
    z[n] = u
    states = np.empty((times.size, n))
    t_prev, h_prev, phi = 0.0, math.nan, np.eye(n + 1)
    for k, t_k in enumerate(times):
        h = t_k - t_prev
        if not math.isclose(h, h_prev, rel_tol=1e-12):
            phi, h_prev = expm(augmented * h), h
        z = phi @ z
        states[k] = z[:n]
        t_prev = t_k
    return states
