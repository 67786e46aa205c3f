"""zmpkit.identify: the robot's deviation from the LIPM, identified from ZMP step trials.

Paper A §4.3–4.4, on arrays (no simulator needed):

- :mod:`~zmpkit.identify.steady_state`: :class:`StepTrial`, the settled window and value of a
  step (:func:`steady_state`);
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
from zmpkit.identify.steady_state import (
    PLANES,
    SteadyState,
    StepTrial,
    effective_sample_size,
    steady_state,
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
    "PLANES",
    "TERMS",
    "BalanceIdentification",
    "BalanceParams",
    "CandidateScore",
    "ErrorModel",
    "ErrorModelFit",
    "PlaneIdentification",
    "PlaneParams",
    "SecondOrderStep",
    "SteadyState",
    "StepTrial",
    "TransientFit",
    "design_matrix",
    "effective_sample_size",
    "fit_error_model",
    "fit_transient",
    "identify_balance",
    "second_order_step",
    "steady_state",
]
