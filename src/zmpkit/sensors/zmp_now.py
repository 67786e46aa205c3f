"""The ZMP of one sample of world-frame wrenches, for a control loop (allocation-free).

The equations of :func:`~zmpkit.sensors.zmp.zmp_in_world` for a single sample, in Python
floats: a walking controller reads its ZMP every tick without numpy temporaries.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["zmp_in_world_now"]


def zmp_in_world_now(
    force_in_world: NDArray[np.float64],
    moment_in_world: NDArray[np.float64],
    sensor_in_world: NDArray[np.float64],
    contact_threshold_n: float,
) -> tuple[float, float] | None:
    """:func:`~zmpkit.sensors.zmp.zmp_in_world` of one sample, in Python floats [m].

    The same equations over the feet in contact, without numpy temporaries (a few
    microseconds instead of a few hundred for two feet); it allocates nothing but its result.

    Args:
        force_in_world: force of each foot [N], shape (F, 3).
        moment_in_world: moment about each sensor origin [N·m], shape (F, 3).
        sensor_in_world: sensor origins [m], shape (F, 3).
        contact_threshold_n: minimum world F_z for contact [N], > 0 (not checked here).

    Returns:
        The ZMP (x, y) [m], or None when no foot is in contact.
    """
    total = num_x = num_y = 0.0
    i, feet = 0, len(force_in_world)
    while i < feet:  # element by element: no temporaries, no iterator objects
        fz = force_in_world.item(i, 2)
        if fz >= contact_threshold_n:
            fx, fy = force_in_world.item(i, 0), force_in_world.item(i, 1)
            tx, ty = moment_in_world.item(i, 0), moment_in_world.item(i, 1)
            ox, oy, oz = (
                sensor_in_world.item(i, 0),
                sensor_in_world.item(i, 1),
                sensor_in_world.item(i, 2),
            )
            total += fz
            num_x += ox * fz - (ty + oz * fx)
            num_y += oy * fz + (tx - oz * fy)
        i += 1
    if total <= 0.0:
        return None
    return num_x / total, num_y / total
