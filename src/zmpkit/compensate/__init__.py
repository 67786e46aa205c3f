"""zmpkit.compensate: compensating the model abstractions of a walk (paper B §III.C, §III.E).

- :mod:`~zmpkit.walking.multibody_zmp`: the ZMP of the whole floating-base robot by
  inverse dynamics (``mj_inverse``), :class:`InverseDynamicsZmp`;
- :mod:`~zmpkit.compensate.algorithm1`: Algorithm 1, the offline iteration that cancels the
  LIPM-vs-multibody ZMP error, :func:`compensate_abstraction`;
- :mod:`~zmpkit.compensate.algorithm2`: Algorithm 2, the online bias-filtered compensation of
  the measured ZMP, :class:`OnlineZmpCompensator`;
- :mod:`~zmpkit.compensate.offsets`: half-sine, sawtooth and Fourier offsets on the desired
  ZMP, :class:`OffsetParameters`;
- :mod:`~zmpkit.compensate.tuning`: tuning an offset's parameters by CMA-ES over simulated
  walks, :func:`tune_offset`.
"""

from __future__ import annotations

from zmpkit.compensate.algorithm1 import Algorithm1Result, compensate_abstraction, zmp_rms
from zmpkit.compensate.algorithm2 import Algorithm2Parameters, OnlineZmpCompensator
from zmpkit.compensate.offsets import OFFSET_SHAPES, OffsetParameters, offset_in_world
from zmpkit.compensate.tuning import TuningResult, tune_offset
from zmpkit.walking.multibody_zmp import InverseDynamicsZmp, MultibodyZmp

__all__ = [
    "OFFSET_SHAPES",
    "Algorithm1Result",
    "Algorithm2Parameters",
    "InverseDynamicsZmp",
    "MultibodyZmp",
    "OffsetParameters",
    "OnlineZmpCompensator",
    "TuningResult",
    "compensate_abstraction",
    "offset_in_world",
    "tune_offset",
    "zmp_rms",
]
