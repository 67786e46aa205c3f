"""Force–torque sensor calibration: axes, signs, units, gains, offsets; ZMP offsets.

A raw sensor sample becomes a wrench ``(F_x, F_y, F_z, τ_x, τ_y, τ_z)`` [N, N·m] in the sensor
frame of :mod:`zmpkit.sensors.zmp` by :meth:`WrenchCalibration.apply`, in this order:

1. permute and sign: ``w_i = signs_i · raw[axis_order_i]``;
2. unit scale: forces (i < 3) times the factor of ``force_unit``, moments times that of
   ``moment_unit`` (:data:`FORCE_UNIT_SCALE`, :data:`MOMENT_UNIT_SCALE`);
3. gain: ``w_i ← gain_i · w_i``;
4. offset: ``w_i ← w_i − offset_i`` (the offset is in [N, N·m]).

JR3 drivers report values scaled by the sensor's full scale, so the unit of a raw channel
depends on the driver. Paper A's balance code divides the moment by 10 before using it
(``x = −(M_y/10 + e F_x)/F_z``), i.e. it reads moments in dN·m; that reading is unverified
(the robot's parameter notes, §5): check it against a known load.

Offsets: :func:`wrench_offset_from_unloaded_window` takes the mean wrench while the feet are in
the air; :func:`zmp_offset_from_standing_window` does what paper A's code does at start-up, the mean
measured ZMP over a window of quiet standing minus where it should be.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite_array
from zmpkit.errors import ParameterError
from zmpkit.sensors.zmp import ZmpSeries

__all__ = [
    "FORCE_UNIT_SCALE",
    "MOMENT_UNIT_SCALE",
    "WrenchCalibration",
    "remove_zmp_offset",
    "wrench_offset_from_unloaded_window",
    "zmp_offset_from_standing_window",
]

FORCE_UNIT_SCALE: Mapping[str, float] = {"N": 1.0, "daN": 10.0, "kgf": 9.80665}
"""Newtons per unit of each force unit [N/unit]."""

MOMENT_UNIT_SCALE: Mapping[str, float] = {
    "N·m": 1.0,
    "N*m": 1.0,
    "Nm": 1.0,
    "dN·m": 0.1,
    "daN·m": 10.0,
    "N·mm": 1e-3,
}
"""Newton-metres per unit of each moment unit [N·m/unit]."""

_IDENTITY_ORDER = (0, 1, 2, 3, 4, 5)

Zmp = TypeVar("Zmp", ZmpSeries, NDArray[np.float64])


def _unit_scale(name: str, unit: str, table: Mapping[str, float]) -> float:
    if unit not in table:
        valid = ", ".join(repr(u) for u in table)
        raise ParameterError(f"unknown {name} {unit!r}; valid: {valid}")
    return table[unit]


def _axis_order(value: ArrayLike) -> NDArray[np.intp]:
    arr = np.asarray(value)
    shown = tuple(arr.tolist()) if arr.ndim == 1 else arr.tolist()
    if arr.shape != (6,) or sorted(shown) != list(_IDENTITY_ORDER):
        raise ParameterError(f"axis_order must be a permutation of {_IDENTITY_ORDER}, got {shown}")
    return _frozen(arr.astype(np.intp))


def _signs(value: ArrayLike) -> NDArray[np.float64]:
    arr = finite_array("signs", value, (6,))
    if not np.all(np.abs(arr) == 1.0):
        raise ParameterError(f"signs must be +1 or -1 each, got {tuple(arr.tolist())}")
    return _frozen(arr)


def _frozen(array: NDArray) -> NDArray:
    array = np.array(array)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class WrenchCalibration:
    """Raw F-T sensor sample → sensor-frame wrench [N, N·m]; see the module for the order.

    Attributes:
        offset: subtracted last, (6,) [N, N, N, N·m, N·m, N·m].
        gain: per-component gain, (6,) [-], > 0.
        axis_order: component i of the wrench is raw component ``axis_order[i]``, (6,).
        signs: ±1 per wrench component, (6,).
        force_unit: unit of the raw forces, a key of :data:`FORCE_UNIT_SCALE`.
        moment_unit: unit of the raw moments, a key of :data:`MOMENT_UNIT_SCALE`.

    Raises:
        ParameterError: on a wrong shape, a non-finite value, a gain <= 0, an axis order that
            is not a permutation of 0..5, a sign other than ±1 or an unknown unit.
    """

    offset: NDArray[np.float64]
    gain: NDArray[np.float64]
    axis_order: NDArray[np.intp]
    signs: NDArray[np.float64]
    force_unit: str
    moment_unit: str

    def __init__(
        self,
        offset: ArrayLike = (0.0,) * 6,
        gain: ArrayLike = (1.0,) * 6,
        axis_order: ArrayLike = _IDENTITY_ORDER,
        signs: ArrayLike = (1.0,) * 6,
        force_unit: str = "N",
        moment_unit: str = "N·m",
    ) -> None:
        # Written out (the dataclass keeps it) so that the vectors may be given as any
        # array-like; they are stored as validated, read-only arrays.
        gain_array = finite_array("gain", gain, (6,))
        if np.any(gain_array <= 0.0):
            raise ParameterError(f"gain must be > 0 each, got {tuple(gain_array.tolist())}")
        _unit_scale("force_unit", force_unit, FORCE_UNIT_SCALE)
        _unit_scale("moment_unit", moment_unit, MOMENT_UNIT_SCALE)
        object.__setattr__(self, "offset", _frozen(finite_array("offset", offset, (6,))))
        object.__setattr__(self, "gain", _frozen(gain_array))
        object.__setattr__(self, "axis_order", _axis_order(axis_order))
        object.__setattr__(self, "signs", _signs(signs))
        object.__setattr__(self, "force_unit", force_unit)
        object.__setattr__(self, "moment_unit", moment_unit)

    @property
    def scale(self) -> NDArray[np.float64]:
        """Overall factor per wrench component, ``signs · unit scale · gain``, (6,)."""
        force = FORCE_UNIT_SCALE[self.force_unit]
        moment = MOMENT_UNIT_SCALE[self.moment_unit]
        units = np.array([force, force, force, moment, moment, moment])
        return self.signs * units * self.gain

    def apply(self, wrench_raw: ArrayLike) -> NDArray[np.float64]:
        """Calibrated sensor-frame wrench [N, N·m], same shape as ``wrench_raw``.

        Args:
            wrench_raw: raw samples, shape (N, 6) or (6,), in the raw axes and units.
        """
        raw = finite_array("wrench_raw", wrench_raw)
        if raw.shape[-1:] != (6,) or raw.ndim > 2:
            raise ParameterError(f"wrench_raw must have shape (6,) or (N, 6), got {raw.shape}")
        return raw[..., self.axis_order] * self.scale - self.offset

    def with_offset(self, offset: ArrayLike) -> WrenchCalibration:
        """A copy with ``offset`` [N, N·m] instead of this one's."""
        return WrenchCalibration(
            offset, self.gain, self.axis_order, self.signs, self.force_unit, self.moment_unit
        )


def _window_mask(time: NDArray[np.float64], window: ArrayLike, name: str) -> NDArray[np.bool_]:
    """Samples with ``t0 <= time <= t1``; raises if there are none."""
    t0, t1 = finite_array(name, window, (2,)).tolist()
    if t0 > t1:
        raise ParameterError(f"{name} must be (t0, t1) with t0 <= t1 [s], got ({t0}, {t1})")
    mask = (time >= t0) & (time <= t1)
    if not np.any(mask):
        covers = f"the data covers t = {time.min()} … {time.max()} s" if time.size else "no samples"
        raise ParameterError(f"{name} ({t0}, {t1}) s holds no samples; {covers}")
    return mask


def wrench_offset_from_unloaded_window(
    wrenches: ArrayLike, time: ArrayLike, window: ArrayLike
) -> NDArray[np.float64]:
    """Mean wrench over a window in which the foot carries no load: the sensor offset.

    Pass wrenches calibrated with a zero offset; the result is then the
    :attr:`WrenchCalibration.offset` to use (see :meth:`WrenchCalibration.with_offset`).

    Args:
        wrenches: sensor-frame wrenches [N, N·m], shape (N, 6).
        time: sample times [s], shape (N,).
        window: (t0, t1) [s], both ends included, with the foot in the air.

    Returns:
        The mean wrench over the window, (6,) [N, N·m].
    """
    time_s = finite_array("time", time, (None,))
    wrench_arr = finite_array("wrenches", wrenches, (time_s.shape[0], 6))
    return wrench_arr[_window_mask(time_s, window, "window")].mean(axis=0)


def _zmp_and_defined(
    zmp: ZmpSeries | ArrayLike, time: ArrayLike | None
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]:
    """``(time, zmp (N, 2), defined)`` from a series or an array whose NaN rows are undefined."""
    if isinstance(zmp, ZmpSeries):
        time_s = zmp.time if time is None else finite_array("time", time, (len(zmp),))
        return time_s, zmp.zmp, zmp.defined
    if time is None:
        raise ParameterError("time is required when zmp is an array rather than a ZmpSeries")
    time_s = finite_array("time", time, (None,))
    arr = np.asarray(zmp, dtype=np.float64)
    if arr.shape != (time_s.shape[0], 2):
        raise ParameterError(
            f"zmp must have shape (N, 2) with N = len(time) = {time_s.shape[0]}, got {arr.shape}"
        )
    defined = ~np.any(np.isnan(arr), axis=1)
    finite_array("zmp (rows that are not NaN)", arr[defined])
    return time_s, arr, defined


def zmp_offset_from_standing_window(
    zmp: ZmpSeries | ArrayLike,
    time: ArrayLike | None,
    window: ArrayLike,
    expected: ArrayLike = (0.0, 0.0),
) -> NDArray[np.float64]:
    """ZMP offset: mean measured ZMP over a window of quiet standing minus ``expected``.

    Paper A's controller does this at start-up with the first samples. Samples where the ZMP is
    undefined (``defined`` False in a series, NaN rows in an array) are left out of the mean.

    Args:
        zmp: a :class:`~zmpkit.sensors.zmp.ZmpSeries`, or ZMP samples (N, 2) [m].
        time: sample times [s], (N,); may be None for a series (its own time is used).
        window: (t0, t1) [s], both ends included.
        expected: where the ZMP truly is while standing, (x, y) in the world frame [m].

    Returns:
        The offset (x, y) [m], to be subtracted by :func:`remove_zmp_offset`.
    """
    time_s, zmp_arr, defined = _zmp_and_defined(zmp, time)
    expected_m = finite_array("expected", expected, (2,))
    in_window = _window_mask(time_s, window, "window")
    usable = in_window & defined
    if not np.any(usable):
        raise ParameterError(
            f"window {tuple(np.asarray(window).tolist())} s holds {np.count_nonzero(in_window)} "
            "samples but the ZMP is undefined (no foot in contact) in all of them"
        )
    return zmp_arr[usable].mean(axis=0) - expected_m


def remove_zmp_offset(zmp: Zmp, offset: ArrayLike) -> Zmp:
    """``zmp − offset``: a new series (or array) whose undefined samples stay NaN.

    Args:
        zmp: a :class:`~zmpkit.sensors.zmp.ZmpSeries` or ZMP samples (N, 2) [m].
        offset: (x, y) [m], e.g. from :func:`zmp_offset_from_standing_window`.
    """
    offset_m = finite_array("offset", offset, (2,))
    if isinstance(zmp, ZmpSeries):
        return dataclasses.replace(zmp, zmp=zmp.zmp - offset_m)
    arr = np.asarray(zmp, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ParameterError(f"zmp must have shape (N, 2), got {arr.shape}")
    return arr - offset_m
