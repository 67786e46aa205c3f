"""The virtual NAO humanoid (H25 V5): primitives-only MJCF, truth parameters, simulation.

The walking model a controller believes is :data:`NAO_WALKING_COM_HEIGHT_M` and the rigid
kinematic model :func:`nao_ik_mjcf`; the simulated truth lives in ``data/truth.yaml`` and is
read only by the simulator and tests.
"""

from zmpkit.robots.nao.model import (
    NAO_DRIVEN_JOINTS,
    NAO_LEG_JOINTS,
    NAO_MASS_KG,
    NAO_SIDES,
    NAO_WALK_COM_HEIGHT_M,
    NAO_WALKING_COM_HEIGHT_M,
    nao_feet_mounts,
)
from zmpkit.robots.nao.preset import make_nao
from zmpkit.robots.nao.robot import (
    NAO_SERVO_LIMITS,
    nao_ik_mjcf,
    nao_ik_model,
    nao_mjcf,
    nao_robot,
)
from zmpkit.robots.nao.truth import DEFAULT_TRUTH_PATH, NaoTruth, load_truth

__all__ = [
    "DEFAULT_TRUTH_PATH",
    "NAO_DRIVEN_JOINTS",
    "NAO_LEG_JOINTS",
    "NAO_MASS_KG",
    "NAO_SERVO_LIMITS",
    "NAO_SIDES",
    "NAO_WALKING_COM_HEIGHT_M",
    "NAO_WALK_COM_HEIGHT_M",
    "NaoTruth",
    "load_truth",
    "make_nao",
    "nao_feet_mounts",
    "nao_ik_mjcf",
    "nao_ik_model",
    "nao_mjcf",
    "nao_robot",
]
