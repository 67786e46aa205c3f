"""A walk's sensor log: what a real robot records while walking, one row per sample.

The file a controller zmpkit does not have gives the simulator fit
(:mod:`zmpkit.simfit.shooting`), and the one ``zmpkit walk`` writes beside its time series
(:data:`WALK_LOG_FILE`) so its own walks can be fitted as if their controller were unknown.
One table, CSV (``.csv``) or Parquet (``.parquet``), one clock, SI units, the column names
of a step dataset's trial CSV (:mod:`zmpkit.experiments.dataset`):

- ``time`` [s], strictly increasing;
- ``cmd_<joint>``: the commanded angle of every driven joint [rad];
- ``enc_<joint>``: its encoder reading [rad] (one ``enc_`` column per ``cmd_`` column);
- ``imu_quat_w``, ``imu_quat_x``, ``imu_quat_y``, ``imu_quat_z``: the IMU orientation in
  the world (gravity-aligned) frame [-];
- ``imu_gyro_{x,y,z}`` [rad/s] and ``imu_acc_{x,y,z}`` [m/s²] in the IMU frame, optional;
- the 12 wrench columns of :data:`zmpkit.io.FT_LOG_COLUMNS` (``right_fx`` … ``left_tz``),
  each foot's wrench on the robot in its sensor frame [N, N·m].

Only sensor-side signals: a log written from a simulated walk holds nothing of the
simulator's hidden state (:func:`walk_log_from_record`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.io import FT_LOG_COLUMNS

__all__ = [
    "IMU_COLUMNS",
    "WALK_LOG_FILE",
    "WalkLog",
    "read_walk_log",
    "walk_log_from_record",
    "write_walk_log",
]

WALK_LOG_FILE = "walk_log.csv"
"""The log ``zmpkit walk`` writes beside ``timeseries.csv``."""
IMU_COLUMNS = (
    *(f"imu_quat_{a}" for a in "wxyz"),
    *(f"imu_gyro_{a}" for a in "xyz"),
    *(f"imu_acc_{a}" for a in "xyz"),
)
"""The IMU columns: quaternion (required), gyro and accelerometer (optional)."""
_MIN_ROWS = 16


@dataclass(frozen=True, eq=False)
class WalkLog:
    """A walk's sensor log on one clock (module docstring).

    Attributes:
        time_s: sample times [s], shape (N,).
        joint_names: the driven joints, columns of the joint arrays.
        q_cmd_rad: commanded angles [rad], shape (N, J).
        q_enc_rad: encoder readings [rad], shape (N, J).
        imu_quat_wxyz: IMU orientation (w, x, y, z) [-], shape (N, 4).
        gyro_rps: gyro, IMU frame [rad/s], shape (N, 3); None if not logged.
        right_wrench: right foot's wrench, sensor frame [N, N·m], shape (N, 6).
        left_wrench: left foot's wrench, sensor frame [N, N·m], shape (N, 6).
        accel_mps2: accelerometer, IMU frame [m/s²], shape (N, 3); None if not logged.
        source: the file read, or ``""``.
    """

    time_s: NDArray[np.float64]
    joint_names: tuple[str, ...]
    q_cmd_rad: NDArray[np.float64]
    q_enc_rad: NDArray[np.float64]
    imu_quat_wxyz: NDArray[np.float64]
    gyro_rps: NDArray[np.float64] | None
    right_wrench: NDArray[np.float64]
    left_wrench: NDArray[np.float64]
    accel_mps2: NDArray[np.float64] | None = None
    source: str = ""

    def wrench(self, foot: str) -> NDArray[np.float64]:
        """``foot``'s wrench (``"right"`` or ``"left"``) [N, N·m], shape (N, 6)."""
        if foot not in ("right", "left"):
            raise ParameterError(f"a walk log has the feet right and left, not {foot!r}")
        return self.right_wrench if foot == "right" else self.left_wrench

    def columns(self) -> dict[str, NDArray[np.float64]]:
        """The log's columns by name (module docstring), ``time`` first."""
        out = {"time": self.time_s}
        out |= {f"cmd_{j}": self.q_cmd_rad[:, k] for k, j in enumerate(self.joint_names)}
        out |= {f"enc_{j}": self.q_enc_rad[:, k] for k, j in enumerate(self.joint_names)}
        imu = (self.imu_quat_wxyz, self.gyro_rps, self.accel_mps2)
        blocks = (IMU_COLUMNS[:4], IMU_COLUMNS[4:7], IMU_COLUMNS[7:])
        for names, values in zip(blocks, imu, strict=True):
            if values is not None:
                out |= {name: values[:, i] for i, name in enumerate(names)}
        wrenches = np.hstack([self.right_wrench, self.left_wrench])
        out |= {name: wrenches[:, i] for i, name in enumerate(FT_LOG_COLUMNS[1:])}
        return out


def walk_log_from_record(record: WalkRecord) -> WalkLog:
    """The sensor log of a simulated walk: commands, encoders, IMU and F-T readings only.

    Raises:
        ParameterError: on a record made without its raw readings, or without both feet.
    """
    sensors = record.sensors
    if sensors is None or set(record.feet) != {"right", "left"}:
        raise ParameterError("a walk log needs the raw readings of the IMU and both feet's F-T")
    return WalkLog(
        record.time_s,
        record.joint_names,
        record.q_cmd_rad,
        record.q_meas_rad,
        sensors.imu_quat_wxyz,
        sensors.gyro_rps,
        sensors.ft_wrench[:, record.feet.index("right")],
        sensors.ft_wrench[:, record.feet.index("left")],
        sensors.accel_mps2,
    )


def write_walk_log(path: Path, log: WalkLog) -> Path:
    """Write ``log`` as CSV (10 significant digits) or, for a ``.parquet`` path, Parquet."""
    columns = log.columns()
    if path.suffix == ".parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        pq.write_table(pa.table(columns), path)
        return path
    header = ",".join(columns)
    table = np.column_stack(list(columns.values()))
    np.savetxt(path, table, delimiter=",", header=header, comments="", fmt="%.10g")
    return path


def read_walk_log(path: str | Path) -> WalkLog:
    """Read a walk log (CSV or Parquet, module docstring).

    Raises:
        InputFileError: naming the file and the column that is missing or wrong.
    """
    path = Path(path)
    columns = _read_columns(path)
    cmd = [c[4:] for c in columns if c.startswith("cmd_")]
    required = ("time", *(f"enc_{j}" for j in cmd), *IMU_COLUMNS[:4], *FT_LOG_COLUMNS[1:])
    missing = [c for c in required if c not in columns]
    if not cmd or missing:
        what = f"missing columns {missing[:4]}" if cmd else "no cmd_<joint> column"
        raise InputFileError(
            path,
            f"{what}; a walk log has time, cmd_<joint> and enc_<joint> per joint, "
            f"imu_quat_w..z and {FT_LOG_COLUMNS[1]}..{FT_LOG_COLUMNS[-1]}",
        )
    for name in required:
        if not np.all(np.isfinite(columns[name])):
            raise InputFileError(path, "expected finite numbers", column=name)
    time = columns["time"]
    if time.size < _MIN_ROWS or np.any(np.diff(time) <= 0.0):
        raise InputFileError(
            path, f"time must rise strictly over at least {_MIN_ROWS} rows", column="time"
        )

    def block(names: tuple[str, ...]) -> NDArray[np.float64] | None:
        if not all(n in columns and np.all(np.isfinite(columns[n])) for n in names):
            return None
        return np.column_stack([columns[n] for n in names])

    quat = np.column_stack([columns[c] for c in IMU_COLUMNS[:4]])
    norm = np.linalg.norm(quat, axis=1)
    if np.any(np.abs(norm - 1.0) > 0.01):
        raise InputFileError(path, "IMU quaternions must have unit norm", column="imu_quat_w")
    wrench = np.column_stack([columns[c] for c in FT_LOG_COLUMNS[1:]])
    return WalkLog(
        time,
        tuple(cmd),
        np.column_stack([columns[f"cmd_{j}"] for j in cmd]),
        np.column_stack([columns[f"enc_{j}"] for j in cmd]),
        quat / norm[:, None],
        block(IMU_COLUMNS[4:7]),
        wrench[:, :6],
        wrench[:, 6:],
        block(IMU_COLUMNS[7:]),
        str(path),
    )


def _read_columns(path: Path) -> dict[str, NDArray[np.float64]]:
    """Every column of the table at ``path``, as float arrays."""
    try:
        if path.suffix == ".parquet":
            import pyarrow.parquet as pq

            table = pq.read_table(path)
            return {
                n: np.asarray(table.column(n).to_numpy(zero_copy_only=False), dtype=np.float64)
                for n in table.column_names
            }
        with path.open(encoding="utf-8-sig") as handle:
            header = handle.readline().strip().split(",")
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except OSError as exc:
        raise InputFileError(path, f"cannot read the walk log: {exc}") from None
    except ValueError as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputFileError(
            path, f"expected {len(header)} numbers per row, as the header names ({first})"
        ) from None
    except Exception as exc:  # pyarrow's own errors
        raise InputFileError(path, f"cannot read the walk log: {exc}") from None
    if data.shape[1] != len(header):
        raise InputFileError(path, f"{data.shape[1]} fields per row, header has {len(header)}")
    return {name: data[:, k] for k, name in enumerate(header)}
