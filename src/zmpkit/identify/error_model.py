r"""Steady-state ZMP error models (paper A eq. 13) and their inverse.

The measured ZMP :math:`x` [m] is a function of the commanded one :math:`u = x_{cmd}` [m]
(the LIPM-expected :math:`l\sin\theta` of the commanded ankle angle). Candidate models:

========================  =============================================
``linear``                :math:`x = b u + c`
``quadratic`` (paper A)   :math:`x = a u^2 + b u + c`
``odd_quadratic``         :math:`x = a u|u| + b u + c` (same softening for ±u)
``cubic``                 :math:`x = d u^3 + a u^2 + b u + c`
========================  =============================================

with :math:`d` [1/m²], :math:`a` [1/m], :math:`b` [-], :math:`c` [m]. Paper A found
a = 0.834, b = 1.024, c = −0.0004 on its robot. :meth:`ErrorModel.invert` gives the command whose
measured ZMP is a target, on the branch through the identity (slope b > 0 at u = 0): for the
quadratic in the cancellation-free closed form

.. math:: u = \frac{2(x - c)}{b + \sqrt{b^2 + 4a(x - c)}}

(finite as a → 0 and at x = c), otherwise by a bracketed root (Brent) polished by one Newton
step. Fitting and choosing among the models: :mod:`zmpkit.identify.error_fit`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from zmpkit._validate import finite, finite_array
from zmpkit.errors import ModelError, ParameterError

__all__ = [
    "COEFFICIENT_UNITS",
    "EQUATIONS",
    "MODEL_KINDS",
    "TERMS",
    "ErrorModel",
    "design_matrix",
]

FloatArray = NDArray[np.float64]

MODEL_KINDS = ("linear", "quadratic", "odd_quadratic", "cubic")
"""Candidate error models, simplest first; ties in complexity prefer the earlier one."""

TERMS = {
    "linear": ("b", "c"),
    "quadratic": ("a", "b", "c"),
    "odd_quadratic": ("a", "b", "c"),
    "cubic": ("d", "a", "b", "c"),
}
"""Coefficient names of each model, in the order of :attr:`ErrorModel.coefficients`."""

EQUATIONS = {
    "linear": "x_ft = b*x_cmd + c",
    "quadratic": "x_ft = a*x_cmd**2 + b*x_cmd + c",
    "odd_quadratic": "x_ft = a*x_cmd*abs(x_cmd) + b*x_cmd + c",
    "cubic": "x_ft = d*x_cmd**3 + a*x_cmd**2 + b*x_cmd + c",
}

COEFFICIENT_UNITS = {"d": "1/m^2", "a": "1/m", "b": "-", "c": "m"}
"""Unit of each coefficient for ZMPs in metres."""

PARSIMONY_MARGIN = 0.10
"""Fraction by which a more complex model must lower the simpler one's LOO RMSE [-]."""

LOO_ABSOLUTE_TOLERANCE_M = 1e-12
"""LOO RMSE differences below this are rounding, not evidence [m]."""


def design_matrix(kind: str, u: FloatArray) -> FloatArray:
    """Columns of the model's terms evaluated at the commands ``u`` [m], shape (n, p)."""
    columns = {
        "d": u**3,
        "a": u * np.abs(u) if kind == "odd_quadratic" else u**2,
        "b": u,
        "c": np.ones_like(u),
    }
    return np.column_stack([columns[name] for name in TERMS[kind]])


def _values(name: str, value: ArrayLike) -> tuple[FloatArray, bool]:
    array = finite_array(name, value)
    return np.atleast_1d(array).astype(np.float64), array.ndim == 0


def _out(values: FloatArray, scalar: bool) -> float | FloatArray:
    return float(values[0]) if scalar else values


def _real_roots(p2: float, p1: float, p0: float) -> list[float]:
    """Finite real roots of :math:`p_2 u^2 + p_1 u + p_0` (stable form; overflow: none)."""
    if p2 == 0.0:
        candidates = [-p0 / p1] if p1 != 0.0 else []
    else:
        discriminant = p1 * p1 - 4.0 * p2 * p0
        if discriminant < 0.0:
            return []
        q = -0.5 * (p1 + math.copysign(math.sqrt(discriminant), p1))
        candidates = [q / p2, p0 / q] if q != 0.0 else [0.0]
    return [r for r in candidates if math.isfinite(r)]


@dataclass(frozen=True)
class ErrorModel:
    """A steady-state error model ``x_measured = f(x_cmd)`` (module docstring).

    Attributes:
        kind: one of :data:`MODEL_KINDS`.
        coefficients: values in the order of ``TERMS[kind]`` (units in :data:`COEFFICIENT_UNITS`).
    """

    kind: str
    coefficients: tuple[float, ...]

    def __post_init__(self) -> None:
        if self.kind not in TERMS:
            raise ParameterError(f"kind must be one of {MODEL_KINDS}, got {self.kind!r}")
        names = TERMS[self.kind]
        if len(self.coefficients) != len(names):
            raise ParameterError(
                f"a {self.kind} error model needs {len(names)} coefficients {names}, "
                f"got {len(self.coefficients)}"
            )
        values = tuple(
            finite(f"coefficient {n}", v) for n, v in zip(names, self.coefficients, strict=True)
        )
        object.__setattr__(self, "coefficients", values)

    @classmethod
    def from_dict(cls, kind: str, coefficients: dict[str, float]) -> ErrorModel:
        """Build from ``{"a": …, "b": …, "c": …}``; raises ParameterError naming a missing one."""
        if kind not in TERMS:
            raise ParameterError(f"kind must be one of {MODEL_KINDS}, got {kind!r}")
        missing = [n for n in TERMS[kind] if n not in coefficients]
        if missing:
            raise ParameterError(f"a {kind} error model needs coefficients {missing}")
        return cls(kind, tuple(coefficients[n] for n in TERMS[kind]))

    @property
    def equation(self) -> str:
        """The model equation as text."""
        return EQUATIONS[self.kind]

    def as_dict(self) -> dict[str, float]:
        """Coefficients by name."""
        return dict(zip(TERMS[self.kind], self.coefficients, strict=True))

    def coefficient(self, name: str) -> float:
        """Coefficient ``name`` (0 for a term the model does not have)."""
        return self.as_dict().get(name, 0.0)

    def _dabc(self) -> tuple[float, float, float, float]:
        return (
            self.coefficient("d"),
            self.coefficient("a"),
            self.coefficient("b"),
            self.coefficient("c"),
        )

    def predict(self, x_cmd: ArrayLike) -> float | FloatArray:
        """Measured ZMP :math:`f(u)` [m] for commanded ZMP ``x_cmd`` [m] (scalar or array)."""
        u, scalar = _values("x_cmd", x_cmd)
        return _out(design_matrix(self.kind, u) @ np.asarray(self.coefficients), scalar)

    def derivative(self, x_cmd: ArrayLike) -> float | FloatArray:
        r"""Slope :math:`f'(u)` [-] at commanded ZMP ``x_cmd`` [m]."""
        u, scalar = _values("x_cmd", x_cmd)
        d, a, b, _ = self._dabc()
        curvature = 2.0 * np.abs(u) if self.kind == "odd_quadratic" else 2.0 * u
        return _out(3.0 * d * u**2 + a * curvature + b, scalar)

    def divided_difference(self, u1: ArrayLike, u0: float) -> float | FloatArray:
        r"""Secant slope :math:`(f(u_1) - f(u_0)) / (u_1 - u_0)` [-], free of cancellation.

        Written out per term (e.g. :math:`u_1 + u_0` for :math:`u^2`), so it is exact as
        :math:`u_1 \to u_0`, where it equals :math:`f'(u_0)`.
        """
        v, scalar = _values("u1", u1)
        w = finite("u0", u0)
        d, a, b, _ = self._dabc()
        if self.kind == "odd_quadratic":
            same_sign = v * w >= 0.0
            mixed = (v**2 + w**2) / np.where(same_sign, 1.0, np.abs(v) + abs(w))
            square = np.where(same_sign, np.abs(v) + abs(w), mixed)
        else:
            square = v + w
        return _out(d * (v**2 + v * w + w**2) + a * square + b, scalar)

    def invert(self, x_target: ArrayLike) -> float | FloatArray:
        """Commanded ZMP [m] whose measured ZMP is ``x_target`` [m], on the identity's branch.

        Raises:
            ModelError: if the slope at x_cmd = 0 is not positive, or a target lies where the
                model is not monotonic (the message names the invertible range).
        """
        x, scalar = _values("x_target", x_target)
        b, c = self.coefficient("b"), self.coefficient("c")
        if b <= 0.0:
            raise ModelError(
                f"the {self.kind} error model ({self.equation}) has slope b = {b:.6g} <= 0 at "
                "x_cmd = 0: the measured ZMP does not follow the command, so it has no inverse"
            )
        if self.kind == "linear":
            return _out((x - c) / b, scalar)
        if self.kind == "quadratic":
            return _out(self._invert_quadratic(x), scalar)
        return _out(self._invert_bracketed(x), scalar)

    def _invert_quadratic(self, x: FloatArray) -> FloatArray:
        _, a, b, c = self._dabc()
        discriminant = b * b + 4.0 * a * (x - c)
        if np.any(discriminant <= 0.0):
            self._raise_range(x, -b / (2.0 * a), float(self.predict(-b / (2.0 * a))))
        return 2.0 * (x - c) / (b + np.sqrt(discriminant))

    def _raise_range(self, x: FloatArray, u_turn: float, x_turn: float) -> NoReturn:
        raise ModelError(
            f"the {self.kind} error model ({self.equation}, {self.as_dict()}) is not monotonic "
            f"beyond x_cmd = {u_turn:.6g} m, where the measured ZMP turns at {x_turn:.6g} m; "
            f"the requested targets span [{x.min():.6g}, {x.max():.6g}] m: keep them on the "
            f"identity's side of {x_turn:.6g} m"
        )

    def monotonic_interval(self) -> tuple[float, float]:
        r"""The interval of :math:`u` [m] around 0 on which :math:`f' > 0` (±inf if unbounded)."""
        d, a, b, _ = self._dabc()
        side = -1.0 if self.kind == "odd_quadratic" else 1.0  # |u| = -u for u < 0
        ahead = [r for r in _real_roots(3.0 * d, 2.0 * a, b) if r > 0.0]
        behind = [r for r in _real_roots(3.0 * d, 2.0 * side * a, b) if r < 0.0]
        return max(behind, default=-math.inf), min(ahead, default=math.inf)

    def _scalar(self, u: float) -> float:
        """:math:`f(u)` for one float, in plain Python (the root finder calls it often)."""
        d, a, b, c = self._dabc()
        square = u * abs(u) if self.kind == "odd_quadratic" else u * u
        return ((d * u) * u + b) * u + a * square + c

    def _invert_bracketed(self, x: FloatArray) -> FloatArray:
        lo, hi = self.monotonic_interval()
        low = self._bracket_end(-1.0, lo, float(x.min()), x)
        high = self._bracket_end(1.0, hi, float(x.max()), x)
        out = np.empty_like(x)
        for i, target in enumerate(x.tolist()):
            u = brentq(lambda v, t=target: self._scalar(v) - t, low, high, xtol=1e-15)
            slope, residual = float(self.derivative(u)), self._scalar(u) - target
            polished = u - residual / slope if slope > 0.0 else u
            better = abs(self._scalar(polished) - target) < abs(residual)
            out[i] = polished if better else u
        return out

    def _bracket_end(self, sign: float, turn: float, target: float, x: FloatArray) -> float:
        """Return a command on side ``sign`` of 0 whose prediction lies beyond ``target``.

        The command lies before the turning point ``turn`` [m] and its prediction beyond
        ``target`` [m]; raises ModelError naming the range if none does.
        """
        h = max(1.0, 2.0 * abs(target))
        while h < abs(turn):
            if sign * (self._scalar(sign * h) - target) > 0.0:
                return sign * h
            h *= 2.0
        with np.errstate(over="ignore", invalid="ignore"):
            x_turn = self._scalar(turn)
        if not sign * (x_turn - target) > 0.0:
            self._raise_range(x, turn, x_turn)
        return turn
