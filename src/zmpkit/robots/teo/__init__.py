"""The virtual TEO humanoid (UC3M): primitives-only MJCF, truth parameters, simulation.

The balance model a controller believes is :data:`TEO_BALANCE_MASS_KG` and
:data:`TEO_COM_HEIGHT_M` (paper A §4.1); the simulated truth lives in
``data/truth.yaml`` and is read only by the simulator and tests.
"""

from zmpkit.robots.teo.model import (
    TEO_BALANCE_MASS_KG,
    TEO_COM_HEIGHT_M,
    TEO_DRIVEN_JOINTS,
    teo_feet_mounts,
)
from zmpkit.robots.teo.preset import make_teo
from zmpkit.robots.teo.robot import TEO_SERVO_LIMITS, teo_mjcf, teo_robot
from zmpkit.robots.teo.truth import DEFAULT_TRUTH_PATH, TeoTruth, load_truth

__all__ = [
    "DEFAULT_TRUTH_PATH",
    "TEO_BALANCE_MASS_KG",
    "TEO_COM_HEIGHT_M",
    "TEO_DRIVEN_JOINTS",
    "TEO_SERVO_LIMITS",
    "TeoTruth",
    "load_truth",
    "make_teo",
    "teo_feet_mounts",
    "teo_mjcf",
    "teo_robot",
]
