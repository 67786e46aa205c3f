"""Write a walk's time series (CSV) and figures into its output folder.

Columns of :data:`SERIES_COLUMNS` (one row per motion frame, SI units, world frame): time;
for the left and right hip, knee and ankle pitch the commanded and measured angle [rad] and
torque [N·m]; trunk pitch and roll from the IMU [rad]; the measured ZMP (empty without
contact) and the planned ZMP reference [m]; each sole centre's position [m] and vertical
force [N]; the torso position [m] and the planned CoM [m].
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from zmpkit.analysis.walk_metrics import (
    CONTACT_FORCE_N,
    amplitude_spectrum,
    double_support_distance,
    measured_zmp,
)
from zmpkit.pipelines.walk_sim import WalkRecord
from zmpkit.walking.pattern import WalkingPattern

if TYPE_CHECKING:
    from zmpkit.pipelines.walk import WalkConfig

__all__ = ["PITCH_JOINTS", "SERIES_COLUMNS", "write_figures", "write_series"]

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


def _planned(values: np.ndarray, n: int) -> np.ndarray:
    """The first ``n`` rows of a planned signal (a record stops early at a fall)."""
    return values[:n]


def write_series(path: Path, pattern: WalkingPattern, record: WalkRecord) -> Path:
    """Write :data:`SERIES_COLUMNS` as CSV; an undefined ZMP is an empty field."""
    n = record.time_s.size
    joints = [record.joint(j) for j in PITCH_JOINTS]
    columns = [record.time_s[:, None]]
    for j in joints:
        columns.append(np.column_stack([record.q_cmd_rad[:, j], record.q_meas_rad[:, j],
                                        record.torque_nm[:, j]]))  # fmt: skip
    zmp = measured_zmp(record.force_in_world, record.moment_in_world, record.sensor_in_world)
    columns += [record.trunk_pitch_rad[:, None], record.trunk_roll_rad[:, None], zmp]
    columns.append(_planned(pattern.zmp_reference_in_world, n))
    for i in range(len(record.feet)):
        columns.append(
            np.column_stack([record.sole_in_world[:, i], record.force_in_world[:, i, 2]])
        )
    columns += [record.torso_in_world, _planned(pattern.com_position_in_world[:, :2], n)]
    table = np.column_stack(columns)
    lines = [",".join(SERIES_COLUMNS)]
    lines += [",".join("" if np.isnan(v) else f"{v:.7g}" for v in row) for row in table]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def write_figures(
    out: Path, config: WalkConfig, pattern: WalkingPattern, record: WalkRecord
) -> dict[str, Path]:
    """Draw paper B's figures of one walk into ``out``; return them by role."""
    from zmpkit.analysis import walk_plots as plots  # matplotlib only when drawing

    label = f"{config.robot.upper()} {config.speed_mps:g} m/s, effects {config.effects}"
    t = record.time_s
    files = {"trunk_pitch": plots.plot_trunk_pitch(t, record.trunk_pitch_rad,
                                                   out / "trunk_pitch.png", label)}  # fmt: skip
    if t.size >= 8:
        spectrum = amplitude_spectrum(record.trunk_pitch_rad, float(np.median(np.diff(t))))
        step_hz = 1.0 / config.step_duration_s
        files["spectrum"] = plots.plot_trunk_spectrum(
            spectrum, step_hz, out / "trunk_pitch_spectrum.png", label
        )
    contact = record.force_in_world[..., 2] >= CONTACT_FORCE_N
    sole_x = record.sole_in_world[..., 0]
    feet = dict(enumerate(record.feet))
    files["feet"] = plots.plot_feet_in_contact(
        t, {f: sole_x[:, i] for i, f in feet.items()}, {f: contact[:, i] for i, f in feet.items()},
        out / "feet_in_contact.png", label,
    )  # fmt: skip
    step_length = abs(config.speed_mps) * config.step_duration_s
    files["feet_distance"] = plots.plot_feet_distance(
        t, double_support_distance(sole_x, contact), step_length,
        out / "feet_distance.png", label,
    )  # fmt: skip
    for joint in ("RAnklePitch", "RKneePitch", "RHipPitch"):
        j = record.joint(joint)
        files[joint] = plots.plot_joint_tracking(
            t, record.q_cmd_rad[:, j], record.q_meas_rad[:, j], record.torque_nm[:, j],
            out / f"joint_{joint}.png", f"{label}: {joint}",
        )  # fmt: skip
    return files
