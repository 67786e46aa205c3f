r"""ZMP from ankle force–torque sensors, vectorised over samples.

Conventions:

- A wrench is ``(F_x, F_y, F_z, τ_x, τ_y, τ_z)`` [N, N, N, N·m, N·m, N·m]: the ground reaction
  transmitted through the sole to the foot, expressed in the sensor frame, moment about the
  sensor origin. In the world frame (z up) ``F_z > 0`` when the foot is loaded.
- A :class:`~zmpkit.sensors.mount.SensorMount` gives the sensor origin ``o`` [m], the
  sensor→world rotation ``R`` and ``h``, the height of ``o`` above the ground under the sole.

Per foot, force and moment are rotated into the world frame, ``F = R F_s``, ``τ_o = R τ_s``.
The centre of pressure ``p`` lies on the ground plane, so ``o − p = (o_x − p_x, o_y − p_y, h)``
and the moment about it is

.. math::
    τ_p = τ_o + (o − p) × F, \quad
    τ_{p,x} = τ_x + (o_y − p_y) F_z − h F_y, \quad
    τ_{p,y} = τ_y + h F_x − (o_x − p_x) F_z .

Setting ``τ_{p,x} = τ_{p,y} = 0`` (the definition of the CoP) gives paper A eq. (5) in both
planes, in the world frame:

.. math::
    p_x = o_x − \frac{τ_y + h F_x}{F_z}, \qquad p_y = o_y + \frac{τ_x − h F_y}{F_z}.

Double support (paper A eq. 6, whose leading minus sign is a typo: eq. 4 is the F_z-weighted
mean), and in general any number of feet:

.. math:: p = \frac{\sum_i p_i F_{z,i}}{\sum_i F_{z,i}} \quad \text{over the feet in contact.}

A foot is in contact when its world ``F_z >= CONTACT_FORCE_THRESHOLD_N`` (overridable: a robot
gives its own, e.g. a lighter robot a lower one). A foot
out of contact contributes nothing; with no foot in contact the ZMP is undefined: it is NaN in
``zmp`` and ``False`` in the ``defined`` mask, which always travels with it. Feet on planes of
different heights are combined as eq. (6) does, as the F_z-weighted mean of their (x, y).

Implementation: ``F_{z,i}`` and ``p_i F_{z,i}`` are linear in the sensor-frame wrench; one (6, 3)
matrix per foot (:func:`moment_coefficients`) gives them, so a series costs one matrix product per
foot and no Python loop over samples.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite_array, in_range
from zmpkit.errors import ParameterError
from zmpkit.sensors.mount import SensorMount

__all__ = [
    "CONTACT_FORCE_THRESHOLD_N",
    "CONTACT_THRESHOLD_RANGE_N",
    "CombinedZmp",
    "FootZmp",
    "ZmpSeries",
    "combined_zmp",
    "contact_threshold",
    "foot_zmp",
    "moment_coefficients",
    "zmp_in_world",
    "zmp_series",
]

CONTACT_FORCE_THRESHOLD_N = 10.0
"""A foot is in contact when its world-frame vertical force is at least this [N]."""
CONTACT_THRESHOLD_RANGE_N = (0.01, 10_000.0)
"""Sane contact thresholds [N]: from 1 gram-force (a small robot's lightest touch) to 10 kN.

Below it an F-T sensor's noise would decide contact (and a ZMP divides by a vanishing
``F_z``); above it no humanoid's foot would ever touch."""


def contact_threshold(value: float, name: str = "contact_threshold_n") -> float:
    """``value`` as a float if it is a sane contact threshold [N], else raise naming ``name``.

    Raises:
        ParameterError: a value outside :data:`CONTACT_THRESHOLD_RANGE_N` or non-finite.
    """
    low, high = CONTACT_THRESHOLD_RANGE_N
    return in_range(name, value, low, high, "N")


def moment_coefficients(mount: SensorMount) -> NDArray[np.float64]:
    """The (6, 3) matrix ``C`` with ``wrench_in_sensor @ C = (F_z, p_x F_z, p_y F_z)`` in world.

    Columns: world ``F_z`` = ``R[2] · F_s``; ``p_x F_z = o_x F_z − (τ_y + h F_x)``;
    ``p_y F_z = o_y F_z + (τ_x − h F_y)``, with ``F = R F_s`` and ``τ = R τ_s`` [N, N·m, N·m].
    """
    rotation, (o_x, o_y, _), h = mount.rotation, mount.position, mount.sole_height
    fz = np.concatenate([rotation[2], np.zeros(3)])
    numerator_x = np.concatenate([h * rotation[0], rotation[1]])  # τ_y + h F_x
    numerator_y = np.concatenate([-h * rotation[1], rotation[0]])  # τ_x − h F_y
    return np.column_stack([fz, o_x * fz - numerator_x, o_y * fz + numerator_y])


@dataclass(frozen=True, eq=False)
class FootZmp:
    """Centre of pressure of one foot.

    Attributes:
        zmp: (x, y) in the world frame [m], shape (N, 2) (or (2,) for one sample); NaN where
            the foot is not in contact — ``contact`` is the mask.
        fz: vertical force in the world frame [N], shape (N,) (or ()).
        contact: ``fz >= threshold``, shape (N,) (or ()).
    """

    zmp: NDArray[np.float64]
    fz: NDArray[np.float64]
    contact: NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class CombinedZmp:
    """ZMP of several feet, F_z-weighted over those in contact.

    Attributes:
        zmp: (x, y) in the world frame [m], shape (N, 2); NaN where undefined.
        defined: at least one foot in contact, shape (N,); ``zmp`` is NaN exactly where False.
        fz: world vertical force of each foot [N], shape (k, N).
        contact: contact of each foot, shape (k, N).
    """

    zmp: NDArray[np.float64]
    defined: NDArray[np.bool_]
    fz: NDArray[np.float64]
    contact: NDArray[np.bool_]


@dataclass(frozen=True, eq=False)
class ZmpSeries:
    """Measured ZMP of a biped over time.

    Attributes:
        time: sample times [s], shape (N,).
        zmp: ZMP (x, y) in the world frame [m], shape (N, 2), column-major so that ``zmp_x``
            and ``zmp_y`` are contiguous. It is NaN where the ZMP is undefined (no foot in
            contact); ``defined`` is that mask and must be used with it.
        defined: at least one foot in contact, shape (N,).
        contact_right: right foot in contact, shape (N,).
        contact_left: left foot in contact, shape (N,).
        fz_right: right foot vertical force in the world frame [N], shape (N,).
        fz_left: left foot vertical force in the world frame [N], shape (N,).
    """

    time: NDArray[np.float64]
    zmp: NDArray[np.float64]
    defined: NDArray[np.bool_]
    contact_right: NDArray[np.bool_]
    contact_left: NDArray[np.bool_]
    fz_right: NDArray[np.float64]
    fz_left: NDArray[np.float64]

    @property
    def zmp_x(self) -> NDArray[np.float64]:
        """ZMP x (forward) in the world frame [m], NaN where undefined."""
        return self.zmp[:, 0]

    @property
    def zmp_y(self) -> NDArray[np.float64]:
        """ZMP y (left) in the world frame [m], NaN where undefined."""
        return self.zmp[:, 1]

    @property
    def n_undefined(self) -> int:
        """Number of samples with no foot in contact."""
        return int(self.defined.size - np.count_nonzero(self.defined))

    def __len__(self) -> int:
        return int(self.time.shape[0])


def _float_array(name: str, value: ArrayLike) -> NDArray[np.float64]:
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an array of real numbers, got {value!r}") from None


def _wrench_array(
    name: str, value: ArrayLike, n: int | None = None, n_from: str = ""
) -> NDArray[np.float64]:
    """``value`` as a finite float64 (N, 6) array (no copy of a float64 one); N = ``n`` if given."""
    arr = _float_array(name, value)
    if n is not None and arr.shape != (n, 6):
        raise ParameterError(
            f"{name} must have shape (N, 6) with N = {n_from} = {n}, got {arr.shape}"
        )
    if arr.ndim != 2 or arr.shape[1] != 6:
        raise ParameterError(f"{name} must have shape (N, 6), got {arr.shape}")
    return finite_array(name, arr)


def _foot_moments(
    wrench: NDArray[np.float64],
    mount: SensorMount,
    threshold_n: float,
    fz_out: NDArray[np.float64],
    contact_out: NDArray[np.bool_],
) -> NDArray[np.float64]:
    """One foot's ``(F_z, p_x F_z, p_y F_z)`` [N, N·m, N·m], shape (3, N), zero out of contact.

    Writes the foot's world F_z [N] into ``fz_out`` and its contact mask into ``contact_out``.
    The (3, N) layout keeps each row contiguous for the element-wise passes that follow.
    """
    moments = moment_coefficients(mount).T @ wrench.T
    fz_out[:] = moments[0]
    np.greater_equal(fz_out, threshold_n, out=contact_out)
    np.copyto(moments, 0.0, where=~contact_out)
    return moments


def _ratio(moments: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(m_x / F_z, m_y / F_z)``, shape (N, 2) (column-major), NaN where all of it is 0.

    Out of contact every foot contributes exactly 0, so an undefined sample is ``0 / 0``:
    NaN by IEEE 754, while a defined one has ``F_z >= threshold > 0``.
    """
    zmp = np.empty((2, moments.shape[1]))
    with np.errstate(invalid="ignore"):
        np.divide(moments[1:], moments[0], out=zmp)
    return zmp.T


def foot_zmp(
    wrench: ArrayLike,
    mount: SensorMount,
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N,
) -> FootZmp:
    """Centre of pressure of one foot (paper A eq. 5 in both planes, world frame).

    Args:
        wrench: sensor-frame wrench (F_x, F_y, F_z, τ_x, τ_y, τ_z) [N, N·m], shape (N, 6),
            or (6,) for one sample (the results then have no sample axis).
        mount: the sensor's pose and height above the sole.
        contact_threshold_n: minimum world F_z for contact [N], in
            :data:`CONTACT_THRESHOLD_RANGE_N`.

    Returns:
        The CoP, NaN where not in contact, with ``fz`` and the ``contact`` mask.
    """
    threshold_n = contact_threshold(contact_threshold_n)
    arr = _float_array("wrench", wrench)
    single = arr.shape == (6,)
    if not single and (arr.ndim != 2 or arr.shape[1] != 6):
        raise ParameterError(f"wrench must have shape (6,) or (N, 6), got {arr.shape}")
    arr = _wrench_array("wrench", arr.reshape(1, 6) if single else arr)
    fz = np.empty(arr.shape[0])
    contact = np.empty(arr.shape[0], dtype=bool)
    zmp = _ratio(_foot_moments(arr, mount, threshold_n, fz, contact))
    if single:
        return FootZmp(zmp[0], fz[0], contact[0])
    return FootZmp(zmp, fz, contact)


def _combine(
    wrenches: Sequence[NDArray[np.float64]], mounts: Sequence[SensorMount], threshold_n: float
) -> CombinedZmp:
    """:func:`combined_zmp` on validated (N, 6) arrays."""
    n = wrenches[0].shape[0]
    fz = np.empty((len(mounts), n))
    contact = np.empty((len(mounts), n), dtype=bool)
    total = _foot_moments(wrenches[0], mounts[0], threshold_n, fz[0], contact[0])
    for i in range(1, len(mounts)):
        total += _foot_moments(wrenches[i], mounts[i], threshold_n, fz[i], contact[i])
    defined = np.any(contact, axis=0)
    return CombinedZmp(_ratio(total), defined, fz, contact)


def combined_zmp(
    wrenches: Sequence[ArrayLike],
    mounts: Sequence[SensorMount],
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N,
) -> CombinedZmp:
    """ZMP of any number of feet: F_z-weighted mean of the CoPs of those in contact (eq. 6).

    Args:
        wrenches: per foot, the sensor-frame wrench [N, N·m], each of shape (N, 6).
        mounts: per foot, its sensor mount; same length as ``wrenches``.
        contact_threshold_n: minimum world F_z for contact [N], in
            :data:`CONTACT_THRESHOLD_RANGE_N`.

    Returns:
        ZMP (NaN where undefined), the ``defined`` mask, and each foot's F_z and contact.
    """
    threshold_n = contact_threshold(contact_threshold_n)
    if len(wrenches) != len(mounts) or len(mounts) == 0:
        raise ParameterError(
            "wrenches and mounts must have the same length >= 1, "
            f"got {len(wrenches)} wrenches and {len(mounts)} mounts"
        )
    first = _wrench_array("wrenches[0]", wrenches[0])
    others = [
        _wrench_array(f"wrenches[{i}]", w, first.shape[0], "len(wrenches[0])")
        for i, w in enumerate(wrenches[1:], start=1)
    ]
    arrays = [first, *others]
    return _combine(arrays, mounts, threshold_n)


def zmp_series(
    time: ArrayLike,
    right_wrench: ArrayLike,
    left_wrench: ArrayLike,
    right: SensorMount,
    left: SensorMount,
    *,
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N,
) -> ZmpSeries:
    """ZMP of a biped from its two ankle F-T sensors over time.

    Args:
        time: sample times [s], shape (N,).
        right_wrench: right sensor-frame wrench [N, N·m], shape (N, 6).
        left_wrench: left sensor-frame wrench [N, N·m], shape (N, 6).
        right: right sensor mount.
        left: left sensor mount.
        contact_threshold_n: minimum world F_z for a foot to be in contact [N], in
            :data:`CONTACT_THRESHOLD_RANGE_N`.

    Returns:
        The series; ``zmp`` is NaN exactly where ``defined`` is False (no foot in contact).

    Raises:
        ParameterError: on a wrong shape, a non-finite value or a threshold outside
            :data:`CONTACT_THRESHOLD_RANGE_N`.
    """
    threshold_n = contact_threshold(contact_threshold_n)
    time_s = finite_array("time", time, (None,))
    n = time_s.shape[0]
    wrenches = [
        _wrench_array("right_wrench", right_wrench, n, "len(time)"),
        _wrench_array("left_wrench", left_wrench, n, "len(time)"),
    ]
    both = _combine(wrenches, [right, left], threshold_n)
    contact, fz = both.contact, both.fz
    return ZmpSeries(time_s, both.zmp, both.defined, contact[0], contact[1], fz[0], fz[1])


def zmp_in_world(
    force_in_world: NDArray[np.float64],
    moment_in_world: NDArray[np.float64],
    sensor_in_world: NDArray[np.float64],
    contact_threshold_n: float = CONTACT_FORCE_THRESHOLD_N,
) -> NDArray[np.float64]:
    r"""ZMP on the floor z = 0 of feet that move, from wrenches already in the world frame [m].

    The walking form of the same equations (module docstring), with each sensor origin ``o``
    given per sample (the feet move) and ``h = o_z``:

    .. math:: p_x = \frac{\sum_i o_{x,i} F_{z,i} - (τ_{y,i} + o_{z,i} F_{x,i})}{\sum_i F_{z,i}},
        \quad p_y = \frac{\sum_i o_{y,i} F_{z,i} + (τ_{x,i} - o_{z,i} F_{y,i})}{\sum_i F_{z,i}}

    over the feet in contact (``F_z >= contact_threshold_n``).

    Args:
        force_in_world: force of each foot [N], shape (N, F, 3).
        moment_in_world: moment about each sensor origin [N·m], shape (N, F, 3).
        sensor_in_world: sensor origins [m], shape (N, F, 3).
        contact_threshold_n: minimum world F_z for contact [N], in
            :data:`CONTACT_THRESHOLD_RANGE_N`.

    Returns:
        The ZMP [m], shape (N, 2); NaN where no foot is in contact.
    """
    threshold_n = contact_threshold(contact_threshold_n)
    fx, fy, fz = (force_in_world[..., i] for i in range(3))
    tx, ty = moment_in_world[..., 0], moment_in_world[..., 1]
    ox, oy, oz = (sensor_in_world[..., i] for i in range(3))
    weight = np.where(fz >= threshold_n, fz, 0.0)
    total = weight.sum(axis=1)
    num_x = np.sum(np.where(weight > 0, ox * fz - (ty + oz * fx), 0.0), axis=1)
    num_y = np.sum(np.where(weight > 0, oy * fz + (tx - oz * fy), 0.0), axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        zmp = np.column_stack([num_x / total, num_y / total])
    zmp[total <= 0.0] = np.nan
    return zmp
