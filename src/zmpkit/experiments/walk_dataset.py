"""The folder a walk writes and the fit reads back: ``summary.json`` and ``timeseries.csv``.

Columns of :data:`SERIES_COLUMNS` (one row per motion frame, SI units, world frame): time;
for the left and right hip, knee and ankle pitch the commanded and measured angle [rad] and
torque [N·m]; trunk pitch and roll from the IMU [rad]; the measured ZMP (empty without
contact) and the planned ZMP reference [m]; each sole centre's position [m] and vertical
force [N]; the torso position [m] and the planned CoM [m].
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError
from zmpkit.experiments.walk_summary import WalkSummary
from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.signals.time_series import Signal, TimeSeries
from zmpkit.walking.pattern import WalkingPattern

__all__ = [
    "PITCH_JOINTS",
    "SERIES_COLUMNS",
    "SERIES_FILE",
    "SUMMARY_FILE",
    "read_series",
    "series_columns",
    "walk_time_series",
    "write_series",
    "write_summary",
    "write_walk_folder",
]

SUMMARY_FILE = "summary.json"
"""The walk's metrics, :class:`~zmpkit.experiments.walk_summary.WalkSummary` as JSON."""
SERIES_FILE = "timeseries.csv"
"""The walk's signals, :data:`SERIES_COLUMNS`."""
PITCH_JOINTS: tuple[str, ...] = tuple(
    f"{s}{j}" for s in ("L", "R") for j in ("HipPitch", "KneePitch", "AnklePitch")
)
"""Joints whose angles and torques the time series keeps (paper B Figs. 7–9)."""
SERIES_COLUMNS: tuple[str, ...] = (
    "time_s",
    *(f"{j}_{q}" for j in PITCH_JOINTS for q in ("cmd_rad", "meas_rad", "torque_nm")),
    "trunk_pitch_rad", "trunk_roll_rad", "zmp_x_m", "zmp_y_m", "zmp_ref_x_m", "zmp_ref_y_m",
    *(f"{f}_{c}" for f in ("left", "right") for c in ("x_m", "y_m", "z_m", "fz_n")),
    "torso_x_m", "torso_y_m", "torso_z_m", "com_ref_x_m", "com_ref_y_m",
)  # fmt: skip


def series_columns(joints: Sequence[str] = PITCH_JOINTS) -> tuple[str, ...]:
    """:data:`SERIES_COLUMNS` with the columns of ``joints`` (a robot's ``series_joints``)."""
    return (
        "time_s",
        *(f"{j}_{q}" for j in joints for q in ("cmd_rad", "meas_rad", "torque_nm")),
        *SERIES_COLUMNS[1 + 3 * len(PITCH_JOINTS) :],
    )


def walk_time_series(
    pattern: WalkingPattern, record: WalkRecord, joints: Sequence[str] = PITCH_JOINTS
) -> TimeSeries:
    """The signals of :func:`series_columns` as a time series (world frame; joints' own axes).

    The planned ZMP and CoM are cut to the record's length (a record stops at a fall).

    Args:
        pattern: the planned walk.
        record: the simulated walk.
        joints: the joints kept (the robot's ``series_joints``; default: the built-in
            walking robot's hip, knee and ankle pitch).
    """
    n = record.time_s.size
    world = [Signal("trunk_pitch", "rad", "world"), Signal("trunk_roll", "rad", "world")]
    columns: list[tuple[Signal, NDArray[np.float64]]] = []
    for joint in joints:
        j = record.joint(joint)
        columns += [
            (Signal(f"{joint}_cmd", "rad", "joint"), record.q_cmd_rad[:, j]),
            (Signal(f"{joint}_meas", "rad", "joint"), record.q_meas_rad[:, j]),
            (Signal(f"{joint}_torque", "N·m", "joint"), record.torque_nm[:, j]),
        ]
    columns += [(world[0], record.trunk_pitch_rad), (world[1], record.trunk_roll_rad)]
    zmp, zmp_ref = record.zmp_in_world(), pattern.zmp_reference_in_world[:n]
    for k, axis in enumerate("xy"):
        columns += [(Signal(f"zmp_{axis}", "m", "world"), zmp[:, k]),
                    (Signal(f"zmp_ref_{axis}", "m", "world"), zmp_ref[:, k])]  # fmt: skip
    for i, foot in enumerate(record.feet):
        columns += [(Signal(f"{foot}_{a}", "m", "world"), record.sole_in_world[:, i, k])
                    for k, a in enumerate("xyz")]  # fmt: skip
        columns.append((Signal(f"{foot}_fz", "N", "world"), record.force_in_world[:, i, 2]))
    com_ref = pattern.com_position_in_world[:n]
    for k, axis in enumerate("xyz"):
        columns.append((Signal(f"torso_{axis}", "m", "world"), record.torso_in_world[:, k]))
    columns += [(Signal(f"com_ref_{a}", "m", "world"), com_ref[:, k]) for k, a in enumerate("xy")]
    series = TimeSeries.from_columns(record.time_s, columns)
    return series.select(series_columns(joints)[1:])


def write_series(
    path: Path, pattern: WalkingPattern, record: WalkRecord, joints: Sequence[str] = PITCH_JOINTS
) -> Path:
    """Write :func:`series_columns` as CSV (7 significant digits); an undefined ZMP is empty."""
    return walk_time_series(pattern, record, joints).write_csv(path, digits=7)


def write_summary(path: Path, summary: WalkSummary) -> Path:
    """Write ``summary`` as JSON."""
    path.write_text(json.dumps(asdict(summary), indent=2) + "\n", encoding="utf-8")
    return path


def write_walk_folder(
    folder: Path,
    summary: WalkSummary,
    pattern: WalkingPattern,
    record: WalkRecord,
    joints: Sequence[str] = (),
) -> Path:
    """Write a walk as the folder the simulator fit reads; returns ``folder``.

    :data:`SUMMARY_FILE` and :data:`SERIES_FILE` of ``joints`` (the robot's series joints;
    empty: :data:`PITCH_JOINTS`).
    """
    folder.mkdir(parents=True, exist_ok=True)
    write_summary(folder / SUMMARY_FILE, summary)
    write_series(folder / SERIES_FILE, pattern, record, tuple(joints) or PITCH_JOINTS)
    return folder


def read_series(
    path: Path, joints: Sequence[str] = PITCH_JOINTS
) -> tuple[list[str], NDArray[np.float64]]:
    """Read a walk's time series: its header and its rows (NaN for an empty ZMP field).

    Args:
        path: the ``timeseries.csv``.
        joints: the walking robot's ``series_joints`` (:func:`series_columns`).

    Raises:
        InputFileError: on a missing column, a short row or a cell that is not a number.
    """
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise InputFileError(path, f"cannot read the walk time series: {exc}") from None
    header = lines[0].split(",") if lines else []
    expected = series_columns(joints)
    missing = [c for c in expected if c not in header]
    if missing:
        raise InputFileError(path, f"missing columns {missing[:4]}; expected {expected}")
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        if len(cells) != len(header):
            raise InputFileError(path, f"{len(cells)} fields, expected {len(header)}", row=number)
        try:
            rows.append([float(c) if c else np.nan for c in cells])
        except ValueError:
            raise InputFileError(
                path, "expected numbers (or empty for no ZMP)", row=number
            ) from None
    table = np.array(rows, dtype=np.float64).reshape(-1, len(header))
    return header, table
