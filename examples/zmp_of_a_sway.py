"""ZMP from two ankle F-T sensors, from Python: a robot sways forward and back on both feet.

Builds the sensor-frame wrenches a JR3-like sensor mounted upside down (rotated π about x,
as on TEO) would report while the centre of pressure moves, then recovers it with
``zmp_series`` (whole series) and ``DoubleSupportZmp`` (one sample, as in a 1 kHz loop).

Run: ``.venv/bin/python examples/zmp_of_a_sway.py``
"""

from __future__ import annotations

import numpy as np

from zmpkit.sensors import DoubleSupportZmp, SensorMount, zmp_series

MASS_KG, G_MPS2 = 62.6, 9.81
SENSOR_HEIGHT_M = 0.010

right = SensorMount.from_rpy([0.0, -0.1285, SENSOR_HEIGHT_M], [np.pi, 0, 0], SENSOR_HEIGHT_M)
left = SensorMount.from_rpy([0.0, 0.1285, SENSOR_HEIGHT_M], [np.pi, 0, 0], SENSOR_HEIGHT_M)

time = np.arange(0.0, 4.0, 0.001)
cop_x = 0.05 * np.sin(2 * np.pi * 0.5 * time)  # each foot's centre of pressure [m]
weight_n = MASS_KG * G_MPS2 / 2  # per foot [N]


def sensor_wrench(mount: SensorMount, cop_x: np.ndarray) -> np.ndarray:
    """Wrench of a vertical load at (cop_x, foot y, ground) in the sensor frame [N, N·m]."""
    n = cop_x.size
    point = np.column_stack([cop_x, np.full(n, mount.position[1]), np.zeros(n)])
    force = np.tile([0.0, 0.0, weight_n], (n, 1))
    moment = np.cross(point - mount.position, force)
    return np.hstack([force @ mount.rotation, moment @ mount.rotation])  # Rᵀ·v, row-wise


series = zmp_series(time, sensor_wrench(right, cop_x), sensor_wrench(left, cop_x), right, left)
print(f"max |zmp_x - cop_x| over {len(series)} samples: {np.abs(series.zmp_x - cop_x).max():.2e} m")

one_sample = DoubleSupportZmp(right, left)
k = 500
wrench_r = sensor_wrench(right, cop_x[k : k + 1])[0].tolist()
wrench_l = sensor_wrench(left, cop_x[k : k + 1])[0].tolist()
print(
    f"one sample at t = {time[k]} s, expected x = {cop_x[k]:.4f} m:", one_sample(wrench_r, wrench_l)
)
