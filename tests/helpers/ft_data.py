"""F-T logs built from known point loads, and the feet file that goes with them."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit.io import FT_LOG_COLUMNS

FEET_YAML = """\
right: {position: [0.0, -0.1285, 0.010], rpy: [3.141592653589793, 0.0, 0.0], sole_height: 0.010}
left:  {position: [0.0,  0.1285, 0.010], rpy: [3.141592653589793, 0.0, 0.0], sole_height: 0.010}
"""


def wrench_in_sensor(
    load_point_in_world: np.ndarray,
    force_in_world: np.ndarray,
    sensor_position: np.ndarray,
    sensor_rotation: np.ndarray,
) -> np.ndarray:
    """Sensor-frame wrench (F, τ about the sensor origin) of a point ground force [N, N·m]."""
    moment_in_world = np.cross(load_point_in_world - sensor_position, force_in_world)
    return np.concatenate([sensor_rotation.T @ force_in_world, sensor_rotation.T @ moment_in_world])


def write_log(path: Path, rows: list[list[float]] | np.ndarray, header=FT_LOG_COLUMNS) -> Path:
    lines = [",".join(header)]
    lines += [",".join(repr(float(v)) if not isinstance(v, str) else v for v in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return path
