"""The step-experiment dataset folder: one CSV per trial plus ``meta.json``.

Layout::

    DIR/meta.json                       robot, seed, effects, settings, sensor mounts,
                                        units of every column, zmpkit version, trials
    DIR/trial_<plane>_<target_mm>.csv   one row per F-T sample

Trial CSV columns (units in ``meta.json["units"]``): ``time`` [s]; the 12 wrench columns of
:data:`zmpkit.io.FT_LOG_COLUMNS` (``right_fx`` … ``left_tz``, sensor frame [N, N·m]);
``enc_<joint>`` encoders [rad]; ``cmd_<joint>`` commanded joint setpoints [rad];
``imu_gyro_{x,y,z}`` [rad/s], ``imu_acc_{x,y,z}`` [m/s²], ``imu_quat_{w,x,y,z}`` [-].

``meta.json["trials"]`` lists each finished trial: file, ``target_m``, ``t_step_s``,
``lean_angle_rad`` and ``startup_window_s`` (the quiet-standing window for the ZMP offset),
and optionally how its hold ended: ``hold_end`` (:data:`~zmpkit.experiments.hold.HOLD_ENDS`,
default ``"hold"``) and ``hold_note``.
``meta.json["sensor_mounts"]`` is the content of a FEET.yaml file.

:func:`read_step_dataset` is the single entry point for reading one back — a simulated sweep
or a real robot's recorded experiment written in the same layout.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.trial_record import StepTrialRecord
from zmpkit.io import FT_LOG_COLUMNS, feet_from_mapping
from zmpkit.sensors import CONTACT_FORCE_THRESHOLD_N, SensorMount, contact_threshold
from zmpkit.signals import PLANES

__all__ = [
    "DATASET_FORMAT",
    "META_FILE",
    "StepDataset",
    "column_units",
    "read_meta",
    "read_step_dataset",
    "read_trial_csv",
    "trial_columns",
    "write_meta",
    "write_trial_csv",
]

DATASET_FORMAT = "zmpkit-step-dataset/1"
"""Value of ``meta.json["format"]``."""
META_FILE = "meta.json"
_IMU = (
    *(f"imu_gyro_{a}" for a in "xyz"),
    *(f"imu_acc_{a}" for a in "xyz"),
    *(f"imu_quat_{a}" for a in "wxyz"),
)
_IMU_UNITS = ("rad/s",) * 3 + ("m/s^2",) * 3 + ("1",) * 4
_META_FIELDS: tuple[str, ...]
_META_FIELDS = ("format", "robot", "plane", "effects", "seed", "settings", "joint_names")
_META_FIELDS += ("sensor_mounts", "units", "zmpkit_version", "lean_length_m", "lean_angle_joints")
_META_FIELDS += ("trials",)
_TRIAL_FIELDS = ("file", "target_m", "t_step_s", "lean_angle_rad", "startup_window_s")
_NUMBER_FORMAT = "%.10g"


@dataclass(frozen=True, eq=False)
class StepDataset:
    """A step-experiment dataset as read from its folder.

    Attributes:
        path: the folder.
        meta: the parsed ``meta.json`` (validated).
        mounts: each foot's F-T sensor mount, from ``meta["sensor_mounts"]``.
        trials: the finished trials, in the order of ``meta["trials"]``.
        contact_threshold_n: the robot's contact threshold, from
            ``meta["contact_threshold_n"]`` (a dataset written before it was recorded: the
            10 N default it was then measured with) [N].
    """

    path: Path
    meta: Mapping[str, Any]
    mounts: Mapping[str, SensorMount]
    trials: tuple[StepTrialRecord, ...]
    contact_threshold_n: float

    @property
    def plane(self) -> str:
        """``"sagittal"`` or ``"frontal"``."""
        return str(self.meta["plane"])

    def startup_window(self, index: int) -> tuple[float, float]:
        """The quiet-standing window (t0, t1) of trial ``index`` [s]."""
        t0, t1 = self.meta["trials"][index]["startup_window_s"]
        return float(t0), float(t1)


def trial_columns(joint_names: tuple[str, ...]) -> tuple[str, ...]:
    """The trial CSV header for these driven joints."""
    return (
        *FT_LOG_COLUMNS,
        *(f"enc_{j}" for j in joint_names),
        *(f"cmd_{j}" for j in joint_names),
        *_IMU,
    )


def column_units(joint_names: tuple[str, ...]) -> dict[str, str]:
    """Unit of every trial CSV column."""
    units = {"time": "s"}
    units |= {c: ("N" if c[-2] == "f" else "N*m") for c in FT_LOG_COLUMNS[1:]}
    units |= {f"{p}_{j}": "rad" for p in ("enc", "cmd") for j in joint_names}
    return units | dict(zip(_IMU, _IMU_UNITS, strict=True))


def _atomic_write(path: Path, text: str) -> None:
    part = path.with_name(f".{path.name}.part")
    part.write_text(text, encoding="utf-8")
    os.replace(part, path)


def write_trial_csv(record: StepTrialRecord, path: str | Path) -> Path:
    """Write one trial's CSV (atomically: a partial file never carries the final name)."""
    path = Path(path)
    table = np.column_stack(
        [
            record.time,
            record.right_wrench,
            record.left_wrench,
            record.encoders,
            record.commanded,
            record.imu,
        ]
    )
    lines = [",".join(trial_columns(record.joint_names))]
    lines += [",".join(_NUMBER_FORMAT % v for v in row) for row in table]
    _atomic_write(path, "\n".join(lines) + "\n")
    return path


def write_meta(meta: Mapping[str, Any], folder: str | Path) -> Path:
    """Write ``meta.json`` into ``folder`` (atomically)."""
    path = Path(folder) / META_FILE
    _atomic_write(path, json.dumps(meta, indent=2, sort_keys=True) + "\n")
    return path


def read_meta(folder: str | Path) -> dict[str, Any]:
    """Read and validate ``meta.json`` of a dataset folder.

    Raises:
        InputFileError: naming the file and the missing or malformed field.
    """
    path = Path(folder) / META_FILE
    try:
        meta = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputFileError(path, "no such file; a step dataset folder holds meta.json") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputFileError(path, f"cannot read as JSON: {exc}") from None
    if not isinstance(meta, dict):
        raise InputFileError(path, "must hold a JSON object")
    for key in _META_FIELDS:
        if key not in meta:
            raise InputFileError(
                path, f"missing field '{key}'; expected: {', '.join(_META_FIELDS)}"
            )
    if meta["format"] != DATASET_FORMAT:
        raise InputFileError(
            path, f"field 'format' must be {DATASET_FORMAT!r}, got {meta['format']!r}"
        )
    if meta["plane"] not in PLANES:
        raise InputFileError(
            path, f"field 'plane' must be one of {', '.join(PLANES)}, got {meta['plane']!r}"
        )
    _check_trials(path, meta["trials"])
    return meta


def _check_trials(path: Path, trials: object) -> None:
    if not isinstance(trials, list):
        raise InputFileError(path, "field 'trials' must be a list")
    for k, entry in enumerate(trials):
        missing = [f for f in _TRIAL_FIELDS if not isinstance(entry, dict) or f not in entry]
        if missing:
            raise InputFileError(path, f"field 'trials[{k}]' is missing '{missing[0]}'")


def _parse_rows(path: Path, lines: list[str], width: int) -> np.ndarray:
    rows = []
    for n, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        if len(cells) != width:
            raise InputFileError(path, f"expected {width} cells, got {len(cells)}", row=n)
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            raise InputFileError(path, f"non-numeric cell in {line[:60]!r}", row=n) from None
    table = np.array(rows, dtype=np.float64).reshape(-1, width)
    if table.shape[0] < 2 or not np.all(np.isfinite(table)):
        raise InputFileError(path, "expected at least 2 rows of finite numbers")
    return table


def read_trial_csv(path: str | Path, meta: Mapping[str, Any], index: int) -> StepTrialRecord:
    """Read trial ``index`` of ``meta["trials"]`` from its CSV at ``path``.

    Raises:
        InputFileError: naming the file, line or column that is wrong.
    """
    path, joints = Path(path), tuple(meta["joint_names"])
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(path, f"cannot read the trial file: {exc}") from None
    header = tuple(lines[0].split(",")) if lines else ()
    want = trial_columns(joints)
    for name in want:
        if name not in header:
            raise InputFileError(path, f"missing column '{name}'", column=name)
    table = _parse_rows(path, lines, len(header))[:, [header.index(c) for c in want]]
    entry, j = meta["trials"][index], len(joints)
    return StepTrialRecord(
        plane=str(meta["plane"]),
        target_m=float(entry["target_m"]),
        t_step_s=float(entry["t_step_s"]),
        lean_angle_rad=float(entry["lean_angle_rad"]),
        lean_length_m=float(meta["lean_length_m"]),
        joint_names=joints,
        time=table[:, 0],
        right_wrench=table[:, 1:7],
        left_wrench=table[:, 7:13],
        encoders=table[:, 13 : 13 + j],
        commanded=table[:, 13 + j : 13 + 2 * j],
        imu=table[:, 13 + 2 * j :],
        hold_end=str(entry.get("hold_end", "hold")),
        hold_note=str(entry.get("hold_note", "")),
    )


def read_step_dataset(folder: str | Path) -> StepDataset:
    """Read a step dataset folder (``meta.json`` + one CSV per trial).

    Raises:
        InputFileError: naming the file and the field, line or column that is wrong.
    """
    folder = Path(folder)
    meta = read_meta(folder)
    mounts = feet_from_mapping(meta["sensor_mounts"], source=folder / META_FILE)
    trials = tuple(
        read_trial_csv(folder / entry["file"], meta, k) for k, entry in enumerate(meta["trials"])
    )
    return StepDataset(folder, meta, mounts, trials, _threshold(folder, meta))


def _threshold(folder: Path, meta: Mapping[str, Any]) -> float:
    """The dataset's contact threshold [N], checked (one line naming the file if not sane)."""
    value = meta.get("contact_threshold_n", CONTACT_FORCE_THRESHOLD_N)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputFileError(
            folder / META_FILE, f"contact_threshold_n: expected a number [N], got {value!r}"
        )
    try:
        return contact_threshold(float(value))
    except ParameterError as exc:
        raise InputFileError(folder / META_FILE, str(exc)) from None
