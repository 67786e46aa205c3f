"""One time-series type: sample times and named signals, each with its unit and frame.

A :class:`TimeSeries` holds ``time_s`` [s], strictly increasing, shape (N,), and a float
table of C columns, shape (N, C), each described by a :class:`Signal`: its name, unit and
frame; N may be 0 (a record with no sample: a simulation that diverged before its first).
Records of experiments (a walk's frames, a step trial's samples, a ZMP series, the
simulator fit's records) give themselves as a :class:`TimeSeries`, so one writer, one
windowing and one column lookup serve them all.

Names follow one rule: the signal's name says *what* (``zmp_x``, ``trunk_pitch``,
``RKneePitch_cmd``, ``left_fz``), the :class:`Signal` says its unit and the frame it is
expressed in; the table's column header is the name with the unit's token appended
(:attr:`Signal.column`): ``zmp_x_m``, ``trunk_pitch_rad``, ``left_fz_n``,
``RKneePitch_torque_nm`` — the columns every zmpkit CSV already uses. NaN marks an
undefined sample (the ZMP without contact), never a number that is wrong.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit.errors import ParameterError

__all__ = ["FRAMES", "UNIT_TOKENS", "Signal", "TimeSeries"]

UNIT_TOKENS: Mapping[str, str] = {
    "s": "s",
    "m": "m",
    "m/s": "mps",
    "m/s^2": "mps2",
    "rad": "rad",
    "rad/s": "rad_s",
    "N": "n",
    "N·m": "nm",
    "Hz": "hz",
    "-": "",
}
"""Units a signal may have, and the token its column header ends with."""
FRAMES: tuple[str, ...] = ("world", "sensor", "sole", "base", "joint", "plane")
"""Frames a signal may be expressed in: the world (x forward, y left, z up), a F-T sensor,
a sole, the robot's base (IMU), a joint's axis, or the trial's plane (sagittal x, frontal y)."""
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9]*(_[A-Za-z0-9]+)*$")


@dataclass(frozen=True)
class Signal:
    """One column of a :class:`TimeSeries`.

    Attributes:
        name: what is measured, e.g. ``"zmp_x"`` (letters, digits, single underscores).
        unit: one of :data:`UNIT_TOKENS`, e.g. ``"m"``, ``"N·m"``; ``"-"`` for a pure number.
        frame: the frame it is expressed in, one of :data:`FRAMES`, or None for a scalar
            that has none (a time, a force magnitude).
    """

    name: str
    unit: str
    frame: str | None = None

    def __post_init__(self) -> None:
        if not _NAME.match(self.name):
            raise ParameterError(
                f"signal name must be letters and digits joined by single underscores, "
                f"got {self.name!r}"
            )
        if self.unit not in UNIT_TOKENS:
            raise ParameterError(
                f"signal {self.name!r}: unit must be one of {', '.join(UNIT_TOKENS)}; "
                f"got {self.unit!r}"
            )
        if self.frame is not None and self.frame not in FRAMES:
            raise ParameterError(
                f"signal {self.name!r}: frame must be one of {', '.join(FRAMES)} or None; "
                f"got {self.frame!r}"
            )

    @property
    def column(self) -> str:
        """The column header: the name, then the unit's token (``zmp_x`` [m] → ``zmp_x_m``)."""
        token = UNIT_TOKENS[self.unit]
        return f"{self.name}_{token}" if token else self.name


def _time_array(time_s: ArrayLike) -> NDArray[np.float64]:
    """``time_s`` as a read-only float64 (N,) array, finite and strictly increasing [s]."""
    try:
        t = np.array(time_s, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError("time_s must be an array of real numbers") from None
    if t.ndim != 1:
        raise ParameterError(f"time_s must have shape (N,), got {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ParameterError(f"time_s must be finite; sample {int(np.argmin(np.isfinite(t)))}")
    if t.size > 1 and np.any(np.diff(t) <= 0.0):
        k = int(np.argmax(np.diff(t) <= 0.0)) + 1
        raise ParameterError(f"time_s must increase strictly; sample {k} does not")
    t.setflags(write=False)
    return t


@dataclass(frozen=True, eq=False)
class TimeSeries:
    """Sample times and named signals (module docstring).

    Attributes:
        time_s: sample times [s], strictly increasing, shape (N,).
        values: the signals, one column each, shape (N, C); NaN where undefined.
        signals: the columns' descriptions, length C, names unique.
    """

    time_s: NDArray[np.float64]
    values: NDArray[np.float64]
    signals: tuple[Signal, ...]

    def __post_init__(self) -> None:
        t = _time_array(self.time_s)
        v = np.array(self.values, dtype=np.float64)
        if v.shape != (t.size, len(self.signals)):
            raise ParameterError(
                f"values must have shape (len(time_s), len(signals)) = "
                f"({t.size}, {len(self.signals)}), got {v.shape}"
            )
        names = [s.name for s in self.signals]
        repeated = sorted({n for n in names if names.count(n) > 1})
        if repeated:
            raise ParameterError(f"signal names must be unique; repeated: {', '.join(repeated)}")
        if np.any(np.isinf(v)):
            column = names[int(np.argmax(np.any(np.isinf(v), axis=0)))]
            raise ParameterError(f"signal {column!r} holds an infinite value")
        v.setflags(write=False)
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "values", v)
        object.__setattr__(self, "signals", tuple(self.signals))

    @classmethod
    def from_columns(
        cls, time_s: ArrayLike, columns: Iterable[tuple[Signal, ArrayLike]]
    ) -> TimeSeries:
        """A series from ``(signal, values)`` pairs, each of shape (N,) or (N, K).

        A (N, K) block fills K consecutive columns; its K signals are given as one
        :class:`Signal` per column, so pass it once per column or split it beforehand.
        """
        signals, blocks = [], []
        for signal, values in columns:
            signals.append(signal)
            blocks.append(np.asarray(values, dtype=np.float64).reshape(-1, 1))
        t = _time_array(time_s)
        table = np.hstack(blocks) if blocks else np.zeros((t.size, 0))
        return cls(t, table, tuple(signals))

    @property
    def names(self) -> tuple[str, ...]:
        """The signals' names, in column order."""
        return tuple(s.name for s in self.signals)

    @property
    def columns(self) -> tuple[str, ...]:
        """The column headers (name and unit token), in column order."""
        return tuple(s.column for s in self.signals)

    def __len__(self) -> int:
        return int(self.time_s.size)

    def index(self, name: str) -> int:
        """Column of the signal ``name`` (or of its header, ``zmp_x_m``)."""
        for i, s in enumerate(self.signals):
            if name in (s.name, s.column):
                return i
        raise ParameterError(f"no signal {name!r}; the series has {', '.join(self.names)}")

    def __getitem__(self, name: str) -> NDArray[np.float64]:
        """The values of one signal, shape (N,) (a read-only view)."""
        return self.values[:, self.index(name)]

    def signal(self, name: str) -> Signal:
        """The description of one signal."""
        return self.signals[self.index(name)]

    def select(self, names: Sequence[str]) -> TimeSeries:
        """The series of the named signals only, in the order given."""
        columns = [self.index(n) for n in names]
        return TimeSeries(
            self.time_s, self.values[:, columns], tuple(self.signals[c] for c in columns)
        )

    def window(self, start_s: float, end_s: float) -> TimeSeries:
        """The samples with ``start_s <= t <= end_s`` [s]; at least one must fall inside."""
        keep = (self.time_s >= start_s) & (self.time_s <= end_s)
        if not np.any(keep):
            raise ParameterError(
                f"no sample in [{start_s}, {end_s}] s; the series spans "
                f"[{self.time_s[0]}, {self.time_s[-1]}] s"
            )
        return TimeSeries(self.time_s[keep], self.values[keep], self.signals)

    def write_csv(self, path: str | Path, digits: int = 7) -> Path:
        """Write ``time_s`` and the columns as CSV (``digits`` significant digits, NaN empty)."""
        path = Path(path)
        table = np.column_stack([self.time_s, self.values])
        lines = [",".join(("time_s", *self.columns))]
        lines += [",".join("" if np.isnan(v) else f"{v:.{digits}g}" for v in row) for row in table]
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return path
