r"""Scalar double-support ZMP for a 1 kHz control loop, in pure Python floats.

Same conventions and result as :mod:`zmpkit.sensors.zmp` (equal to 1e-12 relative), at a
fraction of a microsecond per sample: numpy costs a few microseconds per sample on arrays of
six elements, far more than the arithmetic (see ``benchmarks/bench_zmp.py``).

How: per foot, the world ``F_z``, ``p_x F_z = o_x F_z − (τ_y + h F_x)`` and
``p_y F_z = o_y F_z + (τ_x − h F_y)`` are linear in the six sensor-frame wrench components
(:func:`~zmpkit.sensors.zmp.moment_coefficients`). The feet are combined without a division
per foot,

.. math:: p_x = \frac{\sum_i p_{x,i} F_{z,i}}{\sum_i F_{z,i}} \quad \text{(feet in contact)},

so one call is a few multiply–adds and one or two divisions. The coefficients are written as
literals into a function generated for the two mounts, keeping only the nonzero ones (with
paper A's mount, rotated π about x, at most 3 of 6 per numerator and 1 of 6 for ``F_z``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import cast

import numpy as np
from numpy.typing import NDArray

from zmpkit.sensors.mount import SensorMount
from zmpkit.sensors.zmp import CONTACT_FORCE_THRESHOLD_N, contact_threshold, moment_coefficients

__all__ = ["DoubleSupportZmp"]

ZmpFunction = Callable[[Sequence[float], Sequence[float]], "tuple[float, float] | None"]
ContactsFunction = Callable[[Sequence[float], Sequence[float]], tuple[bool, bool]]

_UNPACK = """\
    r0, r1, r2, r3, r4, r5 = right_wrench
    l0, l1, l2, l3, l4, l5 = left_wrench
    fz_r = {fz_r}
    fz_l = {fz_l}
"""

_ZMP_TEMPLATE = """\
def zmp(right_wrench, left_wrench):
{unpack}\
    if fz_r >= {thr}:
        if fz_l >= {thr}:
            fz = fz_r + fz_l
            return ((({mx_r}) + ({mx_l})) / fz, (({my_r}) + ({my_l})) / fz)
        return (({mx_r}) / fz_r, ({my_r}) / fz_r)
    if fz_l >= {thr}:
        return (({mx_l}) / fz_l, ({my_l}) / fz_l)
    return None


def contacts(right_wrench, left_wrench):
{unpack}\
    return (fz_r >= {thr}, fz_l >= {thr})
"""


def _linear_expression(coefficients: NDArray[np.float64], prefix: str) -> str:
    """Python source of ``Σ c_j · {prefix}j`` over the nonzero ``c_j``; ±1 need no product."""
    terms = []
    for j, c in enumerate(coefficients.tolist()):
        if c == 0.0:
            continue
        sign = "-" if c < 0.0 else "+"
        magnitude = abs(c)
        product = f"{prefix}{j}" if magnitude == 1.0 else f"{magnitude!r} * {prefix}{j}"
        terms.append(f"{sign} {product}")
    if not terms:
        return "0.0"
    source = " ".join(terms)
    return source[2:] if source.startswith("+ ") else "-" + source[2:]


def _generate(
    right: SensorMount, left: SensorMount, threshold_n: float
) -> tuple[str, ZmpFunction, ContactsFunction]:
    """Source and compiled ``(zmp, contacts)`` functions for these two mounts."""
    right_c, left_c = moment_coefficients(right), moment_coefficients(left)
    names = {}
    for side, coefficients, prefix in (("r", right_c, "r"), ("l", left_c, "l")):
        names[f"fz_{side}"] = _linear_expression(coefficients[:, 0], prefix)
        names[f"mx_{side}"] = _linear_expression(coefficients[:, 1], prefix)
        names[f"my_{side}"] = _linear_expression(coefficients[:, 2], prefix)
    unpack = _UNPACK.format(fz_r=names.pop("fz_r"), fz_l=names.pop("fz_l"))
    source = _ZMP_TEMPLATE.format(unpack=unpack, thr=repr(threshold_n), **names)
    namespace: dict[str, object] = {}
    # Only float reprs enter the source: exec runs no user text.
    exec(compile(source, "<zmpkit.sensors.fast.DoubleSupportZmp>", "exec"), namespace)
    # the template defines zmp and contacts with these signatures
    zmp = cast(ZmpFunction, namespace["zmp"])
    return source, zmp, cast(ContactsFunction, namespace["contacts"])


@dataclass(frozen=True, eq=False)
class DoubleSupportZmp:
    """ZMP of two feet from one sample of each ankle F-T sensor, in pure Python floats.

    Args:
        right: right sensor mount.
        left: left sensor mount.
        contact_threshold_n: minimum world F_z for a foot to be in contact [N], in
            :data:`~zmpkit.sensors.zmp.CONTACT_THRESHOLD_RANGE_N`.

    Attributes:
        compute: the generated function behind ``__call__``; bind it to a local in a hot loop
            to save the method call (about 70 ns).
        source: its Python source, for inspection.

    Example:
        >>> zmp = DoubleSupportZmp(right_mount, left_mount)
        >>> zmp([0.0, 0.0, -300.0, 1.5, -6.0, 0.0], [0.0, 0.0, -300.0, 0.0, 0.0, 0.0])
    """

    right: SensorMount
    left: SensorMount
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N
    compute: ZmpFunction = field(init=False, repr=False)
    source: str = field(init=False, repr=False)
    _contacts: ContactsFunction = field(init=False, repr=False)

    def __post_init__(self) -> None:
        threshold_n = contact_threshold(self.contact_threshold_n)
        object.__setattr__(self, "contact_threshold_n", threshold_n)
        # Each coefficient becomes a literal in generated code (LOAD_CONST) instead of an
        # attribute or array lookup: an attribute lookup costs ~30 ns, a numpy element access
        # ~100 ns, and one sample needs up to 30 coefficients. Zero coefficients vanish.
        source, compute, contacts = _generate(self.right, self.left, threshold_n)
        object.__setattr__(self, "source", source)
        object.__setattr__(self, "compute", compute)
        object.__setattr__(self, "_contacts", contacts)

    def __call__(
        self, right_wrench: Sequence[float], left_wrench: Sequence[float]
    ) -> tuple[float, float] | None:
        """The ZMP (x, y) in the world frame [m], or None when no foot is in contact.

        Args:
            right_wrench: right sensor-frame wrench (F_x, F_y, F_z, τ_x, τ_y, τ_z) [N, N·m],
                six floats (a list or tuple; a numpy array works but is slower).
            left_wrench: left sensor-frame wrench, likewise.

        Returns:
            ``(p_x, p_y)`` [m], F_z-weighted over the feet in contact; None if neither is.
        """
        return self.compute(right_wrench, left_wrench)

    def contacts(
        self, right_wrench: Sequence[float], left_wrench: Sequence[float]
    ) -> tuple[bool, bool]:
        """Whether each foot is in contact: ``(F_z,right >= threshold, F_z,left >= threshold)``.

        Args:
            right_wrench: right sensor-frame wrench [N, N·m], six floats.
            left_wrench: left sensor-frame wrench [N, N·m], six floats.
        """
        return self._contacts(right_wrench, left_wrench)
