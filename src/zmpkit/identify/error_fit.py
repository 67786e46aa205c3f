r"""Fitting the steady-state ZMP error model (paper A eq. 13) and choosing among candidates.

:func:`fit_error_model` fits every candidate of :data:`~zmpkit.identify.error_model.MODEL_KINDS`
by weighted least squares and chooses one by leave-one-out cross-validation (LOO-CV) with a
parsimony rule: going through the candidates from the simplest (fewest coefficients; ties in
the order of ``MODEL_KINDS``, so the paper's quadratic before the odd quadratic), a model
replaces the
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

Weights. A steady state's standard error :math:`SE_i` measures only the noise *within* its
trial; trials do not repeat that well (backlash and friction leave the robot in another
state each time, F-T offsets drift: paper A's LIPM errors scatter by about ±3 points of
percent from target to target). Inverse-variance weights :math:`1/SE_i^2` then sit almost
wholly on the quiet trials near 0, and the fit misses the far targets that matter. The
default (``weighting="random_effects"``) adds a between-trial variance that grows with the
target, as a relative scatter does, with a floor for the targets near 0:

.. math:: \sigma_i^2 = SE_i^2 + \tau^2 g_i, \qquad g_i = u_i^2 + u_f^2, \qquad
    w_i = 1/\sigma_i^2

(:math:`u_f` = :data:`SCATTER_FLOOR_M`), with :math:`\tau^2` [-] estimated per candidate
by the method of moments of DerSimonian and Laird (1986), generalised to meta-regression:
with :math:`W_0 = \operatorname{diag}(1/SE_i^2)`, the residual statistic
:math:`Q = \sum_i e_i^2/SE_i^2` has expectation
:math:`(n - p) + \tau^2\,\operatorname{tr}(P G)`, :math:`P = W_0 - W_0 X (X^T W_0 X)^{-1}
X^T W_0`, so

.. math:: \hat\tau^2 = \max\left(0, \frac{Q - (n - p)}{\operatorname{tr}(P G)}\right).

When the trials repeat as well as their noise says, :math:`\hat\tau = 0` and the weights
are the inverse variances; when they scatter, each target's share of the fit tends to its
share in *relative* error, the unit of Table 1. ``"inverse_variance"`` keeps
:math:`1/SE_i^2`, ``"none"`` fits unweighted. The intervals keep the residual scale
(Knapp–Hartung), so they stay honest when :math:`\hat\tau` is itself uncertain.
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
    "SCATTER_FLOOR_M",
    "WEIGHTINGS",
    "CandidateScore",
    "ErrorModelFit",
    "fit_error_model",
]

FloatArray = NDArray[np.float64]

PARSIMONY_MARGIN = 0.20
"""Fraction by which a more complex model must lower the current choice's LOO RMSE [-]."""

LOO_ABSOLUTE_TOLERANCE_M = 1e-12
"""LOO RMSE differences below this are rounding, not evidence [m]."""

SCATTER_FLOOR_M = 0.02
"""Command below which the between-trial scatter stops shrinking with the target [m]."""

WEIGHTINGS = ("random_effects", "inverse_variance", "none")
"""Weighting schemes of :func:`fit_error_model` (module docstring)."""


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
    r"""The chosen error model, its uncertainty and why it was chosen.

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
        scatter: :math:`\hat\tau`, the estimated between-trial scatter relative to
            :math:`g_i` (random effects) [-]; 0 otherwise.
        weighting: the scheme, one of :data:`WEIGHTINGS`.
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
    scatter: float = 0.0
    weighting: str = "none"

    @property
    def weight_shares(self) -> FloatArray:
        r"""Each point's share of the total weight, :math:`w_i / \sum w` [-]."""
        return self.weights / float(np.sum(self.weights))

    @property
    def fitted_range(self) -> tuple[float, float]:
        """Range of the measured ZMPs the model was fitted on [m]: beyond it, extrapolation."""
        return float(np.min(self.x_measured)), float(np.max(self.x_measured))

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


def _score(kind: str, u: FloatArray, y: FloatArray, weights: _Weights) -> CandidateScore:
    p = len(TERMS[kind])
    if u.size < p + 2:
        return CandidateScore(kind, p, None, f"needs at least {p + 2} points, got {u.size}")
    try:
        w = weights.of(kind, u, y)
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


@dataclass(frozen=True)
class _Weights:
    """The weighting scheme and the within-trial variances :math:`SE_i^2` [m²]."""

    scheme: str
    variance: FloatArray | None

    def scatter(self, kind: str, u: FloatArray, y: FloatArray) -> float:
        r""":math:`\hat\tau` of the DerSimonian–Laird estimate (module docstring) [-]."""
        if self.scheme != "random_effects" or self.variance is None:
            return 0.0
        w0 = 1.0 / self.variance
        fit = _least_squares(kind, u, y, w0)
        q = float(np.sum(w0 * fit.residuals**2))
        X = design_matrix(kind, u)
        g = u**2 + SCATTER_FLOOR_M**2
        hat = (X * w0[:, np.newaxis]) @ fit.cov_unscaled @ (X.T * w0)
        trace = float(np.sum(w0 * g) - np.sum(np.diag(hat) * g))
        excess = q - (u.size - X.shape[1])
        return math.sqrt(excess / trace) if excess > 0.0 and trace > 0.0 else 0.0

    def of(self, kind: str, u: FloatArray, y: FloatArray) -> FloatArray:
        """The weights :math:`w_i` of a ``kind`` fit [1/m²]."""
        if self.scheme == "none" or self.variance is None:
            return np.ones_like(u)
        tau = self.scatter(kind, u, y)
        return 1.0 / (self.variance + tau**2 * (u**2 + SCATTER_FLOOR_M**2))


def _inputs(
    x_cmd: ArrayLike, x_measured: ArrayLike, std_errors: ArrayLike | None, weighting: str
) -> tuple[FloatArray, FloatArray, _Weights]:
    u = finite_array("x_cmd", x_cmd, (None,))
    y = finite_array("x_measured", x_measured, (u.size,))
    if weighting not in WEIGHTINGS:
        raise ParameterError(f"weighting must be one of {WEIGHTINGS}, got {weighting!r}")
    if std_errors is None:
        return u, y, _Weights("none", None)
    sigma = finite_array("std_errors", std_errors, (u.size,))
    if np.any(sigma <= 0.0):
        k = int(np.argmax(sigma <= 0.0))
        raise ParameterError(f"std_errors must be > 0 m, got std_errors[{k}] = {sigma[k]} m")
    return u, y, _Weights(weighting, sigma**2)


def fit_error_model(
    x_cmd: ArrayLike,
    x_measured: ArrayLike,
    *,
    std_errors: ArrayLike | None = None,
    candidates: tuple[str, ...] = MODEL_KINDS,
    margin: float = PARSIMONY_MARGIN,
    model: str | None = None,
    confidence: float = 0.95,
    weighting: str = "random_effects",
) -> ErrorModelFit:
    """Fit the steady-state error model (paper A eq. 13) and choose among candidates.

    Args:
        x_cmd: commanded (LIPM-expected) ZMP of each trial [m], shape (n,).
        x_measured: settled measured ZMP of each trial [m], shape (n,).
        std_errors: within-trial standard error of each ``x_measured`` [m]; without them
            the fit is unweighted.
        candidates: models to cross-validate, a subset of :data:`MODEL_KINDS`.
        margin: parsimony margin, the fraction in [0, 1) a more complex model must gain.
        model: force this model instead of the cross-validated choice.
        confidence: level of the confidence intervals, in (0, 1).
        weighting: one of :data:`WEIGHTINGS` (module docstring), used with ``std_errors``.

    Raises:
        ParameterError: malformed inputs or unknown model names (valid ones listed).
        ModelError: too few distinct points for the model(s).
    """
    u, y, w = _inputs(x_cmd, x_measured, std_errors, weighting)
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
    weights: _Weights,
    scores: tuple[CandidateScore, ...],
    reason: str,
    confidence: float,
) -> ErrorModelFit:
    p = len(TERMS[kind])
    if u.size <= p:
        raise ModelError(f"the {kind} error model needs at least {p + 1} points, got {u.size}")
    w = weights.of(kind, u, y)
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
        scatter=weights.scatter(kind, u, y),
        weighting=weights.scheme,
    )
