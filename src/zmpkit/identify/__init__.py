"""zmpkit.identify: the robot's deviation from the LIPM, identified from ZMP step trials.

Paper A §4.3–4.4, on arrays (no simulator needed), from the step trials and settled windows
of :mod:`zmpkit.signals`:

- :mod:`~zmpkit.identify.error_model`: :class:`ErrorModel`, x_FT = f(x_cmd) (eq. 13 and its
  alternatives) and its inverse;
- :mod:`~zmpkit.identify.error_fit`: :func:`fit_error_model`, least squares with confidence
  intervals and the model chosen by leave-one-out cross-validation;
- :mod:`~zmpkit.identify.transient`: overshoot, settling time and a 2nd-order fit per trial;
- :mod:`~zmpkit.identify.params`: :func:`identify_balance` over all trials and
  :class:`BalanceParams`, the YAML file the controller loads.
"""

from __future__ import annotations

from zmpkit.identify.error_fit import (
    LOO_ABSOLUTE_TOLERANCE_M,
    PARSIMONY_MARGIN,
    CandidateScore,
    ErrorModelFit,
    fit_error_model,
)
from zmpkit.identify.error_model import (
    COEFFICIENT_UNITS,
    EQUATIONS,
    MODEL_KINDS,
    TERMS,
    ErrorModel,
    design_matrix,
)
from zmpkit.identify.params import (
    BalanceIdentification,
    BalanceParams,
    PlaneIdentification,
    PlaneParams,
    identify_balance,
)
from zmpkit.identify.transient import (
    PARAMETER_NAMES,
    SecondOrderStep,
    TransientFit,
    fit_transient,
    second_order_step,
)

__all__ = [
    "COEFFICIENT_UNITS",
    "EQUATIONS",
    "LOO_ABSOLUTE_TOLERANCE_M",
    "MODEL_KINDS",
    "PARAMETER_NAMES",
    "PARSIMONY_MARGIN",
    "TERMS",
    "BalanceIdentification",
    "BalanceParams",
    "CandidateScore",
    "ErrorModel",
    "ErrorModelFit",
    "PlaneIdentification",
    "PlaneParams",
    "SecondOrderStep",
    "TransientFit",
    "design_matrix",
    "fit_error_model",
    "fit_transient",
    "identify_balance",
    "second_order_step",
]
