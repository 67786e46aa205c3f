r"""Inverted-pendulum models of a standing humanoid: nonlinear, LIPM, 3-D LIPM, cart-table.

Conventions: x forward, y left, z up; the pendulum angle :math:`\theta` [rad] is positive when
the CoM leans forward (+x), so a static CoM sits at :math:`x = l \sin\theta` above the ZMP
that holds it. Everything is in SI units.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp

from zmpkit._validate import finite, finite_array, positive
from zmpkit.errors import ParameterError, SimulationDivergedError
from zmpkit.models.lti import LinearSystem, _increasing_times

__all__ = [
    "STANDARD_GRAVITY_MPS2",
    "CartTable",
    "InvertedPendulum",
    "Lipm",
    "Lipm3D",
    "LipmTrajectory",
    "PendulumResponse",
]

STANDARD_GRAVITY_MPS2 = 9.81
"""Gravitational acceleration used by default [m/s²] (the value of paper A's code)."""

FloatArray = NDArray[np.float64]
TorqueLaw = Callable[[float, float, float], float]
"""Ankle torque law ``tau(t [s], theta [rad], theta_dot [rad/s]) -> [N·m]``."""


def _values(name: str, value: ArrayLike) -> float | FloatArray:
    """``value`` as a float (scalar input) or float array, checked finite."""
    arr = finite_array(name, value)
    return float(arr) if arr.ndim == 0 else arr


@dataclass(frozen=True, eq=False)
class PendulumResponse:
    r"""Time response of :class:`InvertedPendulum`.

    Attributes:
        t: sample times [s], shape (N,).
        theta: pendulum angle from the vertical [rad], shape (N,).
        theta_dot: angular velocity [rad/s], shape (N,).
        torque: torque :math:`\tau` of eq. 1 at the samples [N·m], shape (N,).
    """

    t: FloatArray
    theta: FloatArray
    theta_dot: FloatArray
    torque: FloatArray


@dataclass(frozen=True)
class InvertedPendulum:
    r"""Nonlinear inverted pendulum (paper A, eq. 1), a point mass on a massless leg.

    .. math::

        \tau = -m l^2 \ddot{\theta} + m g l \sin\theta

    :math:`\tau` [N·m] is the ankle torque in the paper's sign: :math:`\tau = m g l \sin\theta`
    holds the pendulum still at :math:`\theta`; :math:`\tau = 0` lets it fall.

    Attributes:
        mass: point mass at the CoM [kg].
        length: pivot (ankle) to CoM distance [m].
        g: gravitational acceleration [m/s²].
    """

    mass: float
    length: float
    g: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", positive("mass", self.mass, "kg"))
        object.__setattr__(self, "length", positive("length", self.length, "m"))
        object.__setattr__(self, "g", positive("g", self.g, "m/s^2"))

    def angular_acceleration(self, theta: float, torque: float = 0.0) -> float:
        r""":math:`\ddot{\theta} = (m g l \sin\theta - \tau) / (m l^2)` [rad/s²]."""
        m, length = self.mass, self.length
        return (m * self.g * length * math.sin(theta) - torque) / (m * length**2)

    def energy(self, theta: ArrayLike, theta_dot: ArrayLike) -> float | FloatArray:
        r"""Mechanical energy :math:`\tfrac12 m l^2 \dot\theta^2 + m g l \cos\theta` [J].

        Conserved when :math:`\tau = 0`.
        """
        th, om = _values("theta", theta), _values("theta_dot", theta_dot)
        m, length = self.mass, self.length
        return 0.5 * m * length**2 * np.square(om) + m * self.g * length * np.cos(th)

    def expected_zmp(self, theta: ArrayLike) -> float | FloatArray:
        r"""Static ZMP under the CoM at angle ``theta`` [rad]: :math:`x = l\sin\theta` [m]."""
        return self.length * np.sin(_values("theta", theta))

    def expected_zmp_linearised(self, theta: ArrayLike) -> float | FloatArray:
        r"""Small-angle static ZMP :math:`x = l\theta` [m] (the LIPM's)."""
        return self.length * _values("theta", theta)

    def static_angle_for_zmp(self, x: ArrayLike) -> float | FloatArray:
        r"""Angle [rad] that puts the CoM over ZMP ``x`` [m]: :math:`\theta = \arcsin(x/l)`.

        Raises:
            ParameterError: if :math:`|x| > l`; no static posture reaches it.
        """
        zmp = _values("x", x)
        if np.any(np.abs(zmp) > self.length):
            worst = float(np.max(np.abs(zmp)))
            raise ParameterError(
                f"ZMP |x| = {worst} m is out of reach of a pendulum of length l = "
                f"{self.length} m: a static posture needs |x| <= l"
            )
        angle = np.arcsin(np.asarray(zmp) / self.length)
        return float(angle) if angle.ndim == 0 else angle

    def simulate(
        self,
        t: ArrayLike,
        theta0: float,
        theta_dot0: float,
        torque: float | TorqueLaw = 0.0,
        *,
        rtol: float = 1e-10,
        atol: float = 1e-12,
    ) -> PendulumResponse:
        """Integrate eq. 1 with :func:`scipy.integrate.solve_ivp` (DOP853).

        Args:
            t: output times [s], strictly increasing; integration starts at ``t[0]``.
            theta0: initial angle [rad].
            theta_dot0: initial angular velocity [rad/s].
            torque: constant torque [N·m] or a law ``tau(t, theta, theta_dot)``.
            rtol: relative tolerance of the integrator.
            atol: absolute tolerance of the integrator [rad, rad/s].

        Raises:
            SimulationDivergedError: if the integrator fails or leaves finite values.
        """
        times = _increasing_times("t", t)
        constant = 0.0 if callable(torque) else finite("torque", torque)
        law = torque if callable(torque) else (lambda *_: constant)
        y0 = [finite("theta0", theta0), finite("theta_dot0", theta_dot0)]

        def rhs(time: float, state: FloatArray) -> list[float]:
            tau = law(time, state[0], state[1])
            return [state[1], self.angular_acceleration(state[0], tau)]

        sol = solve_ivp(rhs, (times[0], times[-1]), y0, "DOP853", times, rtol=rtol, atol=atol)
        if not sol.success or not np.all(np.isfinite(sol.y)):
            t_end = float(sol.t[-1]) if sol.t.size else float(times[0])
            raise SimulationDivergedError(t_end, "pendulum angle theta", str(sol.message))
        tau = np.array([law(ti, th, om) for ti, th, om in zip(sol.t, *sol.y, strict=True)])
        return PendulumResponse(t=times, theta=sol.y[0], theta_dot=sol.y[1], torque=tau)


@dataclass(frozen=True, eq=False)
class LipmTrajectory:
    """CoM trajectory of a LIPM under a constant ZMP.

    Attributes:
        t: times [s], shape (N,).
        com_position: CoM position [m], shape (N,) (sagittal) or (N, 2) (x, y).
        com_velocity: CoM velocity [m/s], same shape.
        com_acceleration: CoM acceleration [m/s²], same shape.
    """

    t: FloatArray
    com_position: FloatArray
    com_velocity: FloatArray
    com_acceleration: FloatArray


@dataclass(frozen=True)
class _ConstantHeightModel:
    """Point-mass model with the CoM at constant height (paper A, eq. 3: z = z_c)."""

    com_height: float
    g: float = STANDARD_GRAVITY_MPS2

    def __post_init__(self) -> None:
        object.__setattr__(self, "com_height", positive("com_height", self.com_height, "m"))
        object.__setattr__(self, "g", positive("g", self.g, "m/s^2"))

    @property
    def omega(self) -> float:
        r"""Natural frequency :math:`\omega = \sqrt{g / z_c}` [1/s]."""
        return math.sqrt(self.g / self.com_height)


def _closed_form(
    omega: float,
    t: ArrayLike,
    x0: float | FloatArray,
    v0: float | FloatArray,
    zmp: float | FloatArray,
) -> LipmTrajectory:
    """cosh/sinh solution: ``t`` (N,) and scalars give (N,); vectors (k,) give (N, k)."""
    times = finite_array("t", t, (None,))
    wt = omega * (times if np.ndim(x0) == 0 else times[:, np.newaxis])
    offset = x0 - zmp
    x = zmp + offset * np.cosh(wt) + (v0 / omega) * np.sinh(wt)
    v = offset * omega * np.sinh(wt) + v0 * np.cosh(wt)
    return LipmTrajectory(
        t=times, com_position=x, com_velocity=v, com_acceleration=omega**2 * (x - zmp)
    )


@dataclass(frozen=True)
class Lipm(_ConstantHeightModel):
    r"""Sagittal linear inverted pendulum (Kajita): :math:`\ddot{x} = \omega^2 (x - p)`.

    Attributes:
        com_height: height :math:`z_c` of the CoM above the ground [m].
        g: gravitational acceleration [m/s²].
    """

    def state_space(self) -> LinearSystem:
        """State (x [m], ẋ [m/s]), input ZMP p [m], output CoM x [m]."""
        w2 = self.omega**2
        return LinearSystem([[0.0, 1.0], [w2, 0.0]], [[0.0], [-w2]], [[1.0, 0.0]], [[0.0]])

    def closed_form(self, t: ArrayLike, x0: float, v0: float, zmp: float) -> LipmTrajectory:
        r"""Exact trajectory for a constant ZMP ``zmp`` [m] from ``x0`` [m], ``v0`` [m/s].

        .. math::

            x(t) = p + (x_0 - p)\cosh\omega t + \frac{v_0}{\omega}\sinh\omega t
        """
        initial = finite("x0", x0), finite("v0", v0)
        return _closed_form(self.omega, t, *initial, finite("zmp", zmp))

    def orbital_energy(self, x: ArrayLike, v: ArrayLike, zmp: float) -> float | FloatArray:
        r"""Orbital energy :math:`E = \tfrac12 v^2 - \tfrac12\omega^2 (x - p)^2` [m²/s²].

        Constant along every trajectory with constant ZMP ``zmp`` [m].
        """
        pos, vel = _values("x", x), _values("v", v)
        return 0.5 * np.square(vel) - 0.5 * self.omega**2 * np.square(pos - finite("zmp", zmp))


@dataclass(frozen=True)
class Lipm3D(_ConstantHeightModel):
    r"""3-D LIPM: :math:`\ddot{x} = \omega^2 (x - p_x)`, :math:`\ddot{y} = \omega^2 (y - p_y)`.

    Attributes:
        com_height: height :math:`z_c` of the CoM above the ground [m].
        g: gravitational acceleration [m/s²].
    """

    def state_space(self) -> LinearSystem:
        """State (x, y [m], ẋ, ẏ [m/s]), input ZMP (p_x, p_y) [m], output CoM (x, y) [m]."""
        eye, zero, w2 = np.eye(2), np.zeros((2, 2)), self.omega**2
        A = np.block([[zero, eye], [w2 * eye, zero]])
        return LinearSystem(A, np.vstack([zero, -w2 * eye]), np.hstack([eye, zero]), zero)

    def closed_form(
        self, t: ArrayLike, x0: ArrayLike, v0: ArrayLike, zmp: ArrayLike
    ) -> LipmTrajectory:
        """Exact trajectory, each axis as in :meth:`Lipm.closed_form`; arrays of shape (N, 2).

        Args:
            t: times [s], shape (N,).
            x0: initial CoM (x, y) [m].
            v0: initial CoM velocity [m/s].
            zmp: constant ZMP (p_x, p_y) [m].
        """
        vectors = (finite_array(n, v, (2,)) for n, v in (("x0", x0), ("v0", v0), ("zmp", zmp)))
        return _closed_form(self.omega, t, *vectors)

    def orbital_energy(self, xy: ArrayLike, v: ArrayLike, zmp: ArrayLike) -> FloatArray:
        """Orbital energy of each axis [m²/s²], shape (..., 2); see :meth:`Lipm.orbital_energy`."""
        pos, vel = finite_array("xy", xy), finite_array("v", v)
        offset = pos - finite_array("zmp", zmp, (2,))
        return 0.5 * np.square(vel) - 0.5 * self.omega**2 * np.square(offset)


@dataclass(frozen=True)
class CartTable(_ConstantHeightModel):
    r"""Cart-table model (Kajita 2003) for preview control of the ZMP.

    .. math::

        \dddot{x} = u, \qquad p = x - \frac{z_c}{g}\ddot{x}

    Attributes:
        com_height: height :math:`z_c` of the CoM (the cart) above the ground [m].
        g: gravitational acceleration [m/s²].
    """

    def state_space(self) -> LinearSystem:
        """State (x [m], ẋ [m/s], ẍ [m/s²]), input jerk [m/s³], output ZMP p [m]."""
        A = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]
        C = [[1.0, 0.0, -self.com_height / self.g]]
        return LinearSystem(A, [[0.0], [0.0], [1.0]], C, [[0.0]])

    def zmp_from_com(self, x: ArrayLike, xddot: ArrayLike) -> float | FloatArray:
        """ZMP p [m] from CoM position ``x`` [m] and acceleration ``xddot`` [m/s²]."""
        pos, acc = _values("x", x), _values("xddot", xddot)
        return pos - self.com_height / self.g * acc
