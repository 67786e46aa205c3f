"""zmpkit.models: pendulum models of a humanoid (LIPM, cart-table, DLIPM) and LTI helpers."""

from zmpkit.models.dlipm import Dlipm, DlipmStepResponse, paper_units_omega_n
from zmpkit.models.lti import (
    DiscreteLinearSystem,
    DiscreteSimulation,
    LinearSystem,
    zero_order_hold,
)
from zmpkit.models.pendulum import (
    STANDARD_GRAVITY_MPS2,
    CartTable,
    InvertedPendulum,
    Lipm,
    Lipm3D,
    LipmTrajectory,
    PendulumResponse,
)

__all__ = [
    "STANDARD_GRAVITY_MPS2",
    "CartTable",
    "DiscreteLinearSystem",
    "DiscreteSimulation",
    "Dlipm",
    "DlipmStepResponse",
    "InvertedPendulum",
    "LinearSystem",
    "Lipm",
    "Lipm3D",
    "LipmTrajectory",
    "PendulumResponse",
    "paper_units_omega_n",
    "zero_order_hold",
]
