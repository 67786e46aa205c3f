r"""The gain-scheduled DLIPM planner of paper A Fig. 19 as a smooth parametric gain surface.

For a ZMP target :math:`x` [m], the command whose *measured* ZMP is the target comes from
inverting the identified error model :math:`f` (:meth:`ErrorModel.invert`), and the ankle
angle from the pendulum :math:`l` [m]:

.. math:: u(x) = f^{-1}(x), \qquad \theta_{cmd}(x) = \arcsin(u(x) / l)

The offset :math:`c = f(0) \ne 0` makes :math:`\theta_{cmd}(0) \ne 0`, so a pure DC gain
:math:`\theta = K x` is singular at :math:`x = 0`. The schedule therefore splits the angle
into a constant feed-forward and a DLIPM whose DC gain is a secant slope:

.. math::

    \theta = \theta_0 + K(x)\,x, \qquad \theta_0 = \theta_{cmd}(0), \qquad
    K(x) = \frac{\theta_{cmd}(x) - \theta_0}{x} \;\to\; \theta_{cmd}'(0) \;(x \to 0)

:math:`K` is evaluated without cancellation. With :math:`u_0 = f^{-1}(0)`,
:math:`s_i = u_i/l`, :math:`c_i = \sqrt{1 - s_i^2}` and the secant slope
:math:`q = (f(u) - f(u_0))/(u - u_0) = x/(u - u_0)`, written per term
(:meth:`ErrorModel.divided_difference`),

.. math::

    \sin(\theta_{cmd} - \theta_0) = z = \frac{x\,r}{l\,q}, \quad
    r = c_0 + \frac{s_0 (s + s_0)}{c_0 + c}, \qquad
    K(x) = \frac{r}{l\,q}\,\frac{\arcsin z}{z}

so :math:`K` is analytic through :math:`x = 0`, where it equals
:math:`1/(l\,c_0\,f'(u_0)) = \theta_{cmd}'(0)`, and across ± targets. The DLIPM (eq. 11,
mass explicit, :class:`~zmpkit.models.Dlipm`) then gets, for the damping ratio ζ,

.. math::

    \beta = \gamma / K, \quad \alpha = 2\zeta\sqrt\beta, \quad
    k_a = m l \beta + m g \;[N], \quad B_a = m l \alpha \;[N\!\cdot\!s]

A few coefficients (those of f, m, l, g, ζ) define the whole surface: no lookup table.

Fitted range. f is known only over the measured ZMPs it was fitted on
(:attr:`GainSchedule.fitted_range`). Beyond it the schedule *extrapolates* the fitted
polynomial as it is (the rule: no clamping, so a target keeps its meaning; a clamp would
silently move it); :meth:`GainSchedule.extrapolates` says which targets do, so a caller can
warn about them.

How this differs from paper A's coded law (the robot's parameter notes §8,
:func:`paper_a_coded_gains`): its code sets :math:`k_a = g + (k_{a,const}(r) - g)\,f(r)/r` with
k_a per kg and an ad-hoc :math:`k_{a,const}(r) = 0.25 r + 9.95`, i.e. it *evaluates* f at
the target instead of inverting it (the angle :math:`\propto r^2/f(r)` matches
:math:`f^{-1}(r)` only to first order in :math:`f(r) - r`); it has no feed-forward for c;
it computes :math:`B_a` from :math:`\omega_n = \sqrt{k_a - g}/L` where the model's is
:math:`\sqrt{(k_a - g)/L}`; and it falls back to :math:`k_a = 9.95` whenever
:math:`f(r) < 10^{-11}`: for every negative target and for
:math:`0 \le r \lesssim 0.39` mm. Just above that threshold :math:`f(r)/r \to 0`, so
:math:`k_a \to g`, :math:`\beta \to 0` and the DC gain diverges: the law is discontinuous
at r ≈ 0.39 mm and ignores negative references, where this one is continuous, finite,
exact for the fitted f, and treats ± targets alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite_array, non_negative, positive
from zmpkit.errors import ModelError
from zmpkit.identify.error_model import ErrorModel
from zmpkit.identify.params import BalanceParams
from zmpkit.models.dlipm import Dlipm
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2

__all__ = ["DEFAULT_ZETA", "EXTRAPOLATION_TOLERANCE_M", "GainSchedule", "paper_a_coded_gains"]

FloatArray = NDArray[np.float64]

DEFAULT_ZETA = 0.8
"""Damping ratio of the scheduled DLIPM, paper A §4.4 [-]."""

EXTRAPOLATION_TOLERANCE_M = 1e-3
"""A target within this of the fitted range counts as inside it (the measured ZMP of the
trial at 0 is not exactly 0) [m]."""

_ASIN_SERIES_LIMIT = 1e-4
"""Below this |z|, asin(z)/z = 1 + z²/6 + 3z⁴/40 (error < 1e-25) [-]."""


def _asin_over(z: FloatArray) -> FloatArray:
    """asin(z)/z, equal to 1 at z = 0."""
    small = np.abs(z) < _ASIN_SERIES_LIMIT
    safe = np.where(small, 1.0, z)
    return np.where(small, 1.0 + z**2 / 6.0 + 3.0 * z**4 / 40.0, np.arcsin(safe) / safe)


def _out(values: FloatArray, scalar: bool) -> float | FloatArray:
    return float(values[0]) if scalar else values


@dataclass(frozen=True, eq=False)
class GainSchedule:
    r"""Smooth gain surface of the DLIPM over the ZMP target (module docstring).

    Every method is vectorised: a scalar target gives a float, an array an array.

    Attributes:
        error_model: the identified x_measured = f(x_cmd) of this plane.
        mass: pendulum mass [kg].
        length: pendulum length, ankle to CoM [m].
        zeta: damping ratio of the scheduled DLIPM [-].
        g: gravitational acceleration [m/s²].
        fitted_range: range of measured ZMPs f was fitted on (low, high) [m]; None: unknown.
        theta_offset: :math:`\theta_0 = \arcsin(f^{-1}(0)/l)`, the constant feed-forward [rad].
    """

    error_model: ErrorModel
    mass: float
    length: float
    zeta: float = DEFAULT_ZETA
    g: float = STANDARD_GRAVITY_MPS2
    fitted_range: tuple[float, float] | None = None
    theta_offset: float = field(init=False)
    _u0: float = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", positive("mass", self.mass, "kg"))
        object.__setattr__(self, "length", positive("length", self.length, "m"))
        object.__setattr__(self, "zeta", non_negative("zeta", self.zeta))
        object.__setattr__(self, "g", positive("g", self.g, "m/s^2"))
        u0 = float(self._commands(np.zeros(1))[0])
        object.__setattr__(self, "_u0", u0)
        object.__setattr__(self, "theta_offset", math.asin(u0 / self.length))

    @classmethod
    def from_params(
        cls, params: BalanceParams, plane: str, *, zeta: float = DEFAULT_ZETA
    ) -> GainSchedule:
        """The schedule of ``plane`` from identified :class:`BalanceParams`."""
        p = params.plane(plane)
        return cls(p.error_model, params.mass, params.com_height, zeta, params.g)

    def _commands(self, x: FloatArray) -> FloatArray:
        """:math:`u = f^{-1}(x)` [m], checked to lie inside the pendulum, |u| < l."""
        u = np.asarray(self.error_model.invert(x), dtype=np.float64)
        if np.any(np.abs(u) >= self.length):
            raise ModelError(
                f"the targets [{x.min():.6g}, {x.max():.6g}] m need commands up to "
                f"{np.abs(u).max():.6g} m, not below the pendulum length {self.length} m"
            )
        return u

    def extrapolates(self, x_ref: float) -> bool:
        """Whether ``x_ref`` [m] lies outside :attr:`fitted_range` by more than 1 mm.

        (:data:`EXTRAPOLATION_TOLERANCE_M`).
        """
        if self.fitted_range is None:
            return False
        low, high = self.fitted_range
        tol = EXTRAPOLATION_TOLERANCE_M
        return not low - tol <= x_ref <= high + tol

    def commanded_zmp(self, x_ref: ArrayLike) -> float | FloatArray:
        """The commanded (LIPM-expected) ZMP whose measured ZMP is ``x_ref`` [m] → [m]."""
        x, scalar = _targets(x_ref)
        return _out(self._commands(x), scalar)

    def commanded_angle(self, x_ref: ArrayLike) -> float | FloatArray:
        r""":math:`\theta_{cmd} = \arcsin(f^{-1}(x)/l)` [rad] for target ``x_ref`` [m]."""
        x, scalar = _targets(x_ref)
        return _out(np.arcsin(self._commands(x) / self.length), scalar)

    def dc_gain(self, x_ref: ArrayLike) -> float | FloatArray:
        r""":math:`K(x)` [rad/m], the DLIPM's DC gain, finite and analytic through 0."""
        x, scalar = _targets(x_ref)
        return _out(self._gain(x), scalar)

    def _gain(self, x: FloatArray) -> FloatArray:
        u, length = self._commands(x), self.length
        s0, s1 = self._u0 / length, u / length
        c0, c1 = math.sqrt(1.0 - s0 * s0), np.sqrt(1.0 - s1 * s1)
        q = np.asarray(self.error_model.divided_difference(u, self._u0), dtype=np.float64)
        ratio = (c0 + s0 * (s1 + s0) / (c0 + c1)) / (length * q)
        gain = ratio * _asin_over(x * ratio)
        if np.any(gain <= 0.0):
            raise ModelError(f"the DC gain K(x) must be > 0 rad/m, got min {gain.min():.6g}")
        return gain

    def steady_angle(self, x_ref: ArrayLike) -> float | FloatArray:
        r""":math:`\theta_0 + K(x)\,x` [rad], the angle the scheduled DLIPM settles to."""
        x, scalar = _targets(x_ref)
        return _out(self.theta_offset + self._gain(x) * x, scalar)

    def beta(self, x_ref: ArrayLike) -> float | FloatArray:
        r""":math:`\beta = \gamma / K` [1/s²]."""
        x, scalar = _targets(x_ref)
        return _out(self.g / self.length**2 / self._gain(x), scalar)

    def alpha(self, x_ref: ArrayLike) -> float | FloatArray:
        r""":math:`\alpha = 2\zeta\sqrt\beta` [1/s]."""
        return 2.0 * self.zeta * np.sqrt(self.beta(x_ref))

    def k_a(self, x_ref: ArrayLike) -> float | FloatArray:
        r"""Ankle spring :math:`k_a = m l \beta + m g` [N] for target ``x_ref`` [m]."""
        return self.mass * (self.length * self.beta(x_ref) + self.g)

    def b_a(self, x_ref: ArrayLike) -> float | FloatArray:
        r"""Ankle damper :math:`B_a = m l \alpha` [N·s] for target ``x_ref`` [m]."""
        return self.mass * self.length * self.alpha(x_ref)

    def dlipm(self, x_ref: float) -> Dlipm:
        """The scheduled :class:`~zmpkit.models.Dlipm` for one target ``x_ref`` [m]."""
        return Dlipm(self.mass, self.length, float(self.k_a(x_ref)), float(self.b_a(x_ref)), self.g)


def _targets(x_ref: ArrayLike) -> tuple[FloatArray, bool]:
    array = finite_array("x_ref", x_ref)
    return np.atleast_1d(array).astype(np.float64), array.ndim == 0


def paper_a_coded_gains(
    zmp_ref: ArrayLike,
    *,
    mass: float = 62.589,
    length: float = 0.8927,
    g: float = STANDARD_GRAVITY_MPS2,
    chi: float = 1.0,
    fit: tuple[float, float, float] = (0.834, 1.024, -0.0004),
) -> tuple[FloatArray, FloatArray]:
    r"""Paper A's coded scheduling law (the robot's parameter notes §8), for comparison only.

    :math:`k_{a,const} = 0.25 r + 9.95`, :math:`k_a = g + (k_{a,const} - g) f(r)/r`, falling
    back to 9.95 when r = 0 or :math:`f(r) < 10^{-11}`; :math:`B_a = 2\chi M\sqrt{k_a - g}`
    as coded. Defaults are the constants of the code (W ``global.h``, ``LIPM2d.cpp``).

    Args:
        zmp_ref: ZMP references r [m].
        mass: M [kg].
        length: L [m].
        g: gravity [m/s²].
        chi: χ [-].
        fit: (a, b, c) of the code's steady-state fit f.

    Returns:
        ``(k_a, B_a)``: k_a per unit mass [N/kg] and B_a as coded [N·s], arrays like r.
    """
    r = np.atleast_1d(finite_array("zmp_ref", zmp_ref)).astype(np.float64)
    a, b, c = fit
    zmp_ft = a * r**2 + b * r + c
    k_const = 0.25 * r + 9.95
    fallback = (r == 0.0) | (zmp_ft < 1e-11)
    safe_r = np.where(fallback, 1.0, r)
    k_a = np.where(fallback, 9.95, g + (k_const - g) * zmp_ft / safe_r)
    return k_a, 2.0 * chi * mass * np.sqrt(np.maximum(k_a - g, 0.0))
