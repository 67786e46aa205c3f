r"""Fitting the steady-state ZMP error model (paper A eq. 13) and choosing among candidates.

:func:`fit_error_model` fits every candidate of :data:`~zmpkit.identify.error_model.MODEL_KINDS`
by (weighted) least squares, weights :math:`w_i = 1/\sigma_i^2` from the steady-state standard
errors, and chooses one by leave-one-out cross-validation (LOO-CV) with a parsimony rule:
going through the candidates from the simplest (fewest coefficients; ties in the order of
``MODEL_KINDS``, so the paper's quadratic before the odd quadratic), a model replaces the
current choice only if it lowers the LOO RMSE by more than ``margin`` (default 20 %) of the
current one's (and by more than :data:`LOO_ABSOLUTE_TOLERANCE_M`). With 11 targets over
0–0.10 m and 0.2 mm noise, 20 % keeps the linear model for linear data and finds paper A's
quadratic for its data in about 95 % of random draws each (10 %: about 85 % and 90 %).

The LOO residuals of a linear least-squares fit are exact in closed form,
:math:`e_{(i)} = e_i / (1 - h_{ii})` with the leverages :math:`h_{ii}`; the score is
:math:`\sqrt{\sum w_i e_{(i)}^2 / \sum w_i}` [m]. The chosen model's covariance is
:math:`s^2 (X^T W X)^{-1}` with :math:`s^2 = \sum w_i e_i^2 / (n - p)` (the weights fix the
relative, the residuals the absolute scale), and its confidence intervals use Student's t
with n − p degrees of freedom.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import solve_triangular
from scipy.stats import t as student_t

from zmpkit._validate import finite, finite_array
from zmpkit.errors import ModelError, ParameterError
from zmpkit.identify.error_model import MODEL_KINDS, TERMS, ErrorModel, design_matrix

__all__ = [
    "LOO_ABSOLUTE_TOLERANCE_M",
    "PARSIMONY_MARGIN",
    "CandidateScore",
    "ErrorModelFit",
    "fit_error_model",
]

FloatArray = NDArray[np.float64]

PARSIMONY_MARGIN = 0.20
"""Fraction by which a more complex model must lower the current choice's LOO RMSE [-]."""

LOO_ABSOLUTE_TOLERANCE_M = 1e-12
"""LOO RMSE differences below this are rounding, not evidence [m]."""


@dataclass(frozen=True)
class CandidateScore:
    """Leave-one-out cross-validation score of one candidate model.

    Attributes:
        kind: the candidate (one of :data:`MODEL_KINDS`).
        n_params: its number of coefficients.
        loo_rmse: weighted RMS of the leave-one-out residuals [m]; None if not scored.
        note: why it was not scored; empty otherwise.
    """

    kind: str
    n_params: int
    loo_rmse: float | None
    note: str = ""


@dataclass(frozen=True, eq=False)
class ErrorModelFit:
    """The chosen error model, its uncertainty and why it was chosen.

    Attributes:
        model: the fitted :class:`ErrorModel`.
        std_errors: standard error of each coefficient, in ``TERMS[kind]`` order.
        confidence_intervals: (low, high) of each coefficient at ``confidence``.
        confidence: the confidence level of the intervals, e.g. 0.95.
        residuals: measured − predicted at each point [m], shape (n,).
        r_squared: (weighted) coefficient of determination; None if the data are constant.
        dof: degrees of freedom n − p.
        scores: LOO-CV score of every candidate.
        reason: how the model was chosen.
        x_cmd: commanded ZMPs fitted [m], shape (n,).
        x_measured: measured ZMPs fitted [m], shape (n,).
        weights: weights of the fit [1/m²], shape (n,) (ones when unweighted).
    """

    model: ErrorModel
    std_errors: tuple[float, ...]
    confidence_intervals: tuple[tuple[float, float], ...]
    confidence: float
    residuals: FloatArray
    r_squared: float | None
    dof: int
    scores: tuple[CandidateScore, ...]
    reason: str
    x_cmd: FloatArray
    x_measured: FloatArray
    weights: FloatArray

    @property
    def kind(self) -> str:
        """Name of the chosen model."""
        return self.model.kind

    @property
    def loo_rmse(self) -> dict[str, float | None]:
        """LOO RMSE [m] of every candidate, by name."""
        return {score.kind: score.loo_rmse for score in self.scores}

    def interval(self, name: str) -> tuple[float, float]:
        """Confidence interval of coefficient ``name``."""
        return self.confidence_intervals[self._index(name)]

    def std_error(self, name: str) -> float:
        """Standard error of coefficient ``name``."""
        return self.std_errors[self._index(name)]

    def _index(self, name: str) -> int:
        names = TERMS[self.model.kind]
        if name not in names:
            raise ParameterError(
                f"the {self.model.kind} model has coefficients {names}, not {name!r}"
            )
        return names.index(name)

    def predict(self, x_cmd: ArrayLike) -> float | FloatArray:
        """See :meth:`ErrorModel.predict`."""
        return self.model.predict(x_cmd)

    def invert(self, x_target: ArrayLike) -> float | FloatArray:
        """See :meth:`ErrorModel.invert`."""
        return self.model.invert(x_target)


@dataclass(frozen=True)
class _LeastSquares:
    coefficients: FloatArray
    residuals: FloatArray
    cov_unscaled: FloatArray
    leverage: FloatArray


def _least_squares(kind: str, u: FloatArray, y: FloatArray, w: FloatArray) -> _LeastSquares:
    X = design_matrix(kind, u)
    sw = np.sqrt(w)
    Q, R = np.linalg.qr(X * sw[:, np.newaxis])
    diagonal = np.abs(np.diag(R))
    if diagonal.min() <= 1e-12 * diagonal.max():
        raise ModelError(
            f"the {kind} error model cannot be fitted: its {X.shape[1]} terms are not "
            f"independent over x_cmd = {np.unique(u).tolist()} m (too few distinct commands)"
        )
    coefficients = solve_triangular(R, Q.T @ (y * sw))
    r_inv = solve_triangular(R, np.eye(R.shape[0]))
    return _LeastSquares(coefficients, y - X @ coefficients, r_inv @ r_inv.T, np.sum(Q**2, axis=1))


def _score(kind: str, u: FloatArray, y: FloatArray, w: FloatArray) -> CandidateScore:
    p = len(TERMS[kind])
    if u.size < p + 2:
        return CandidateScore(kind, p, None, f"needs at least {p + 2} points, got {u.size}")
    try:
        fit = _least_squares(kind, u, y, w)
    except ModelError as exc:
        return CandidateScore(kind, p, None, str(exc))
    keep = 1.0 - fit.leverage
    if keep.min() <= 1e-12:
        return CandidateScore(kind, p, math.inf, "a point has leverage 1: LOO undefined")
    loo = fit.residuals / keep
    return CandidateScore(kind, p, math.sqrt(float(np.sum(w * loo**2) / np.sum(w))))


def _choose(scores: list[CandidateScore], margin: float) -> tuple[str, str]:
    """The candidate kept by the parsimony rule (module docstring), and the reason."""
    ranked = sorted(
        (s for s in scores if s.loo_rmse is not None),
        key=lambda s: (s.n_params, MODEL_KINDS.index(s.kind)),
    )
    if not ranked:
        reasons = "; ".join(f"{s.kind}: {s.note}" for s in scores)
        raise ModelError(f"no candidate error model can be cross-validated ({reasons})")
    best, notes = ranked[0], list[str]()
    for cand in ranked[1:]:
        assert cand.loo_rmse is not None
        assert best.loo_rmse is not None
        gain = best.loo_rmse - cand.loo_rmse
        beats = gain > margin * best.loo_rmse and gain > LOO_ABSOLUTE_TOLERANCE_M
        verb = "beats" if beats else "does not beat"
        notes.append(
            f"{cand.kind} (LOO RMSE {cand.loo_rmse * 1e3:.4g} mm) {verb} {best.kind} "
            f"({best.loo_rmse * 1e3:.4g} mm) by more than {margin:.0%}"
        )
        best = cand if beats else best
    notes += [f"{s.kind} not scored: {s.note}" for s in scores if s.loo_rmse is None]
    return best.kind, (
        f"{best.kind} chosen by leave-one-out cross-validation, simplest first, a model with "
        f"as many or more coefficients replacing the choice only if it lowers the LOO RMSE by "
        f"more than {margin:.0%}: " + "; ".join(notes or ["the only candidate"])
    )


def _inputs(
    x_cmd: ArrayLike, x_measured: ArrayLike, std_errors: ArrayLike | None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    u = finite_array("x_cmd", x_cmd, (None,))
    y = finite_array("x_measured", x_measured, (u.size,))
    if std_errors is None:
        return u, y, np.ones_like(u)
    sigma = finite_array("std_errors", std_errors, (u.size,))
    if np.any(sigma <= 0.0):
        k = int(np.argmax(sigma <= 0.0))
        raise ParameterError(f"std_errors must be > 0 m, got std_errors[{k}] = {sigma[k]} m")
    return u, y, 1.0 / sigma**2


def fit_error_model(
    x_cmd: ArrayLike,
    x_measured: ArrayLike,
    *,
    std_errors: ArrayLike | None = None,
    candidates: tuple[str, ...] = MODEL_KINDS,
    margin: float = PARSIMONY_MARGIN,
    model: str | None = None,
    confidence: float = 0.95,
) -> ErrorModelFit:
    """Fit the steady-state error model (paper A eq. 13) and choose among candidates.

    Args:
        x_cmd: commanded (LIPM-expected) ZMP of each trial [m], shape (n,).
        x_measured: settled measured ZMP of each trial [m], shape (n,).
        std_errors: standard error of each ``x_measured`` [m]; weights 1/σ² when given.
        candidates: models to cross-validate, a subset of :data:`MODEL_KINDS`.
        margin: parsimony margin, the fraction in [0, 1) a more complex model must gain.
        model: force this model instead of the cross-validated choice.
        confidence: level of the confidence intervals, in (0, 1).

    Raises:
        ParameterError: malformed inputs or unknown model names (valid ones listed).
        ModelError: too few distinct points for the model(s).
    """
    u, y, w = _inputs(x_cmd, x_measured, std_errors)
    unknown = [k for k in (*candidates, *([model] if model else [])) if k not in TERMS]
    if unknown or not candidates:
        raise ParameterError(f"models must be among {MODEL_KINDS}, got {unknown or candidates}")
    if (
        not 0.0 <= finite("margin", margin) < 1.0
        or not 0.0 < finite("confidence", confidence) < 1.0
    ):
        raise ParameterError(
            f"need 0 <= margin < 1 and 0 < confidence < 1, got {margin}, {confidence}"
        )
    scores = [_score(kind, u, y, w) for kind in candidates]
    if model is None:
        kind, reason = _choose(scores, margin)
    else:
        kind, reason = model, f"{model} chosen by the caller (LOO-CV scores kept for reference)"
    return _final_fit(kind, u, y, w, tuple(scores), reason, confidence)


def _final_fit(
    kind: str,
    u: FloatArray,
    y: FloatArray,
    w: FloatArray,
    scores: tuple[CandidateScore, ...],
    reason: str,
    confidence: float,
) -> ErrorModelFit:
    p = len(TERMS[kind])
    if u.size <= p:
        raise ModelError(f"the {kind} error model needs at least {p + 1} points, got {u.size}")
    fit = _least_squares(kind, u, y, w)
    dof = u.size - p
    ss_res = float(np.sum(w * fit.residuals**2))
    se = np.sqrt(np.diag(fit.cov_unscaled) * ss_res / dof)
    half = float(student_t.ppf(0.5 + confidence / 2.0, dof)) * se
    beta = fit.coefficients
    ss_tot = float(np.sum(w * (y - np.sum(w * y) / np.sum(w)) ** 2))
    return ErrorModelFit(
        model=ErrorModel(kind, tuple(float(v) for v in beta)),
        std_errors=tuple(float(v) for v in se),
        confidence_intervals=tuple(
            (float(b - h), float(b + h)) for b, h in zip(beta, half, strict=True)
        ),
        confidence=confidence,
        residuals=fit.residuals,
        r_squared=None if ss_tot == 0.0 else 1.0 - ss_res / ss_tot,
        dof=dof,
        scores=scores,
        reason=reason,
        x_cmd=u,
        x_measured=y,
        weights=w,
    )
