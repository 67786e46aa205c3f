r"""Transient of a ZMP step (paper A §4.4): overshoot, settling time and a 2nd-order fit.

The measured ZMP after a step at :math:`t_s` is fitted by a second-order step with dead
time :math:`\tau`,

.. math::

    y(t) = y_0 + \Delta\, s(t - t_s - \tau), \qquad
    \frac{S(p)}{U(p)} = \frac{\omega_n^2}{p^2 + 2\zeta\omega_n p + \omega_n^2}

where :math:`s` is the unit step response (:math:`s = 0` for negative time), by
:func:`scipy.optimize.least_squares` over :math:`(y_0, \Delta, \zeta, \omega_n, \tau)`
from a few starts (the best kept). Standard errors are
:math:`\sqrt{\operatorname{diag}(\hat s^2 (J^T J)^{-1})}`, inflated by
:math:`n / n_{eff}` for autocorrelated residuals
(:func:`~zmpkit.signals.robust_statistics.effective_sample_size`). The static gain is
:math:`\Delta / (x_{cmd} - x_{cmd,before})` [-].

A fit that fails — no step above the noise, a parameter stuck on its bound, a singular
Jacobian — gives ``ok=False`` with the reason, and no parameters (never NaN).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import OptimizeResult, least_squares

from zmpkit._validate import positive
from zmpkit.signals.robust_statistics import MAD_TO_SIGMA, effective_sample_size
from zmpkit.signals.steady_state import SteadyState, steady_state
from zmpkit.signals.step_metrics import StepMetrics, step_metrics
from zmpkit.signals.step_trial import StepTrial

__all__ = [
    "PARAMETER_NAMES",
    "SecondOrderStep",
    "TransientFit",
    "fit_transient",
    "second_order_step",
]

FloatArray = NDArray[np.float64]

PARAMETER_NAMES = ("initial_value", "step_size", "zeta", "omega_n", "dead_time")
"""Parameters of :class:`SecondOrderStep`, in the order of its ``std_errors``."""

ZETA_BOUNDS = (0.01, 10.0)
_MAX_GUESS_OVERSHOOT = 0.9  # largest overshoot [-] the starting ζ is derived from
"""Search range of the damping ratio [-]."""

MIN_STEP_NOISE_RATIO = 5.0
"""A step smaller than this many noise standard deviations is not fitted [-]."""


def second_order_step(t: ArrayLike, zeta: float, omega_n: float) -> FloatArray:
    r"""Unit step response :math:`s(t)` of :math:`\omega_n^2/(p^2 + 2\zeta\omega_n p + \omega_n^2)`.

    Args:
        t: time since the step [s]; s = 0 where t < 0.
        zeta: damping ratio [-], > 0.
        omega_n: natural frequency [rad/s], > 0.
    """
    tt = np.maximum(np.asarray(t, dtype=np.float64), 0.0)
    sigma, q = zeta * omega_n, omega_n**2 * (1.0 - zeta**2)
    if abs(q) <= 1e-10 * omega_n**2:  # critically damped
        return 1.0 - np.exp(-omega_n * tt) * (1.0 + omega_n * tt)
    if q > 0.0:
        wd = math.sqrt(q)
        return 1.0 - np.exp(-sigma * tt) * (np.cos(wd * tt) + sigma / wd * np.sin(wd * tt))
    nu = math.sqrt(-q)
    slow, fast = np.exp((nu - sigma) * tt), np.exp(-(nu + sigma) * tt)
    return 1.0 - 0.5 * (slow + fast) - sigma * (slow - fast) / (2.0 * nu)


@dataclass(frozen=True)
class SecondOrderStep:
    r"""A fitted second-order step with dead time (module docstring).

    Attributes:
        initial_value: :math:`y_0` [m].
        step_size: :math:`\Delta` [m].
        zeta: damping ratio [-].
        omega_n: natural frequency [rad/s].
        dead_time: :math:`\tau` [s].
        t_step: time of the step [s].
        std_errors: standard errors in :data:`PARAMETER_NAMES` order (units as above).
    """

    initial_value: float
    step_size: float
    zeta: float
    omega_n: float
    dead_time: float
    t_step: float
    std_errors: tuple[float, ...]

    def std_error(self, name: str) -> float:
        """Standard error of parameter ``name`` (one of :data:`PARAMETER_NAMES`)."""
        return self.std_errors[PARAMETER_NAMES.index(name)]

    def response(self, t: ArrayLike) -> FloatArray:
        """The model's ZMP at times ``t`` [s] → [m]."""
        shifted = np.asarray(t, dtype=np.float64) - self.t_step - self.dead_time
        return self.initial_value + self.step_size * second_order_step(
            shifted, self.zeta, self.omega_n
        )

    @property
    def overshoot_pct(self) -> float:
        r"""Model overshoot :math:`100\,e^{-\pi\zeta/\sqrt{1-\zeta^2}}` [%] (0 if ζ >= 1)."""
        if self.zeta >= 1.0:
            return 0.0
        return 100.0 * math.exp(-math.pi * self.zeta / math.sqrt(1.0 - self.zeta**2))


@dataclass(frozen=True)
class TransientFit:
    r"""Transient of one trial.

    Attributes:
        ok: whether the second-order fit succeeded.
        message: why it failed, or a summary when it succeeded.
        metrics: overshoot, settling time etc. measured on the samples (None if undefined);
            noise adds to the measured peak, the model's ``overshoot_pct`` does not see it.
        model: the fitted second-order step; None when ``ok`` is False.
        gain: :math:`\Delta / (x_{cmd} - x_{cmd,before})` [-]; None without a fit or command step.
        rms_residual: RMS of the fit residuals [m]; None without a fit.
        noise_std: robust noise estimate of the samples, MAD of differences / √2 [m].
    """

    ok: bool
    message: str
    metrics: StepMetrics | None
    model: SecondOrderStep | None
    gain: float | None
    rms_residual: float | None
    noise_std: float

    @property
    def overshoot_pct(self) -> float | None:
        """Measured overshoot [%] (see :class:`~zmpkit.signals.step_metrics.StepMetrics`)."""
        return None if self.metrics is None else self.metrics.overshoot_pct

    @property
    def settling_time_s(self) -> float | None:
        """Measured settling time after the step [s]."""
        return None if self.metrics is None else self.metrics.settling_time_s

    @property
    def zeta(self) -> float | None:
        """Fitted damping ratio [-], None when the fit failed."""
        return None if self.model is None else self.model.zeta

    @property
    def omega_n(self) -> float | None:
        """Fitted natural frequency [rad/s], None when the fit failed."""
        return None if self.model is None else self.model.omega_n


def _initial_value(trial: StepTrial) -> float:
    before = trial.zmp_measured[trial.time < trial.t_step]
    if before.size >= 3:
        return float(np.median(before))
    return float(np.interp(trial.t_step, trial.time, trial.zmp_measured))


def _measure(trial: StepTrial, steady: SteadyState, band: float) -> StepMetrics | None:
    final = steady.value if steady.settled else None
    y0 = _initial_value(trial)
    if final is not None and final == y0:
        return None
    return step_metrics(
        trial.time,
        trial.zmp_measured,
        t_step=trial.t_step,
        initial_value=y0,
        final_value=final,
        reference=trial.zmp_ref,
        settling_band=band,
    )


def _guesses(metrics: StepMetrics, span_s: float) -> list[tuple[float, float]]:
    """Starting (ζ, ω_n) pairs from the measured overshoot, peak and rise times."""
    overshoot = (metrics.overshoot_pct or 0.0) / 100.0
    if overshoot > 0.005:
        # A measured overshoot beyond 100 % (the ZMP of a real lean can exceed any
        # 2nd-order step) would give ζ < 0: start lightly damped instead.
        log_m = math.log(min(overshoot, _MAX_GUESS_OVERSHOOT))
        zeta = min(0.95, -log_m / math.sqrt(math.pi**2 + log_m**2))
        omega = math.pi / max(metrics.peak_time_s, 1e-6) / math.sqrt(1.0 - zeta**2)
    else:
        zeta = 1.0
        rise = metrics.rise_time_s or span_s / 10.0
        omega = 3.4 / max(rise, 1e-6)
    return [(zeta, omega), (0.7, omega), (zeta, 2.0 * omega), (zeta, 0.5 * omega)]


def fit_transient(
    trial: StepTrial,
    steady: SteadyState | None = None,
    *,
    dead_time: bool = True,
    max_dead_time_s: float = 0.5,
    settling_band: float = 0.02,
) -> TransientFit:
    """Measure and fit the transient of ``trial`` (module docstring).

    Args:
        trial: the step trial.
        steady: its steady state (computed with defaults when omitted).
        dead_time: whether to fit a dead time τ (else τ = 0).
        max_dead_time_s: upper bound of τ [s].
        settling_band: settling band, a fraction of the step, for the measured settling time.
    """
    steady = steady_state(trial) if steady is None else steady
    max_tau = positive("max_dead_time_s", max_dead_time_s, "s")
    noise = MAD_TO_SIGMA * float(np.median(np.abs(np.diff(trial.zmp_measured)))) / math.sqrt(2)
    metrics = _measure(trial, steady, settling_band)
    if metrics is None or abs(metrics.step_size) < MIN_STEP_NOISE_RATIO * noise:
        size = 0.0 if metrics is None else abs(metrics.step_size)
        message = (
            f"no transient to fit: the step {size:.3g} m is below {MIN_STEP_NOISE_RATIO:g} "
            f"times the noise (σ = {noise:.3g} m)"
        )
        return TransientFit(False, message, metrics, None, None, None, noise)
    return _fit(trial, metrics, noise, max_tau if dead_time else 0.0)


def _fit(trial: StepTrial, metrics: StepMetrics, noise: float, max_tau: float) -> TransientFit:
    t, y = trial.time, trial.zmp_measured
    span = float(t[-1] - trial.t_step)
    omega_max = math.pi / float(np.median(np.diff(t)))
    lower = [-np.inf, -np.inf, ZETA_BOUNDS[0], 2.0 * math.pi / span, 0.0]
    upper = [np.inf, np.inf, ZETA_BOUNDS[1], omega_max, max(max_tau, 1e-12)]
    n_params = 5 if max_tau > 0.0 else 4
    if not lower[3] < upper[3]:  # no ω_n with one period recorded yet below Nyquist
        message = (
            f"too little recorded after the step to fit: {span:.3g} s at a sample period of "
            f"{math.pi / omega_max:.3g} s (a 2nd-order fit needs more than two samples)"
        )
        return TransientFit(False, message, metrics, None, None, None, noise)

    def residual(p: FloatArray) -> FloatArray:
        tau = p[4] if n_params == 5 else 0.0
        return p[0] + p[1] * second_order_step(t - trial.t_step - tau, p[2], p[3]) - y

    best = None
    for zeta, omega in _guesses(metrics, span):
        start = [metrics.initial_value, metrics.step_size, zeta, omega, 0.0][:n_params]
        start[3] = min(max(start[3], lower[3] * 1.01), omega_max * 0.99)
        bounds = (lower[:n_params], upper[:n_params])
        result = least_squares(residual, start, bounds=bounds, x_scale="jac")
        if best is None or result.cost < best.cost:
            best = result
    assert best is not None
    return _judge(trial, metrics, noise, best, (lower, upper), n_params)


def _judge(
    trial: StepTrial,
    metrics: StepMetrics,
    noise: float,
    result: OptimizeResult,
    bounds: tuple[list[float], list[float]],
    n_params: int,
) -> TransientFit:
    """Turn the least-squares result into a TransientFit, flagging an unusable fit."""
    p, r = result.x, result.fun
    rms = float(np.sqrt(np.mean(r**2)))
    fail = None
    if not result.success:
        fail = f"least squares did not converge: {result.message}"
    for i, name in ((2, "zeta"), (3, "omega_n")):
        for bound in (bounds[0][i], bounds[1][i]):
            if fail is None and abs(p[i] - bound) <= 1e-6 * max(1.0, abs(bound)):
                fail = f"{name} = {p[i]:.4g} stuck on its bound {bound:.4g}: not a 2nd-order step"
    jtj = result.jac.T @ result.jac
    scale = np.sqrt(np.diag(jtj))
    if fail is None and (
        np.any(scale == 0.0) or np.linalg.cond(jtj / np.outer(scale, scale)) > 1e12
    ):
        fail = "the Jacobian is singular: the parameters are not identifiable from this response"
    if fail is not None:
        return TransientFit(False, fail, metrics, None, None, rms, noise)
    dof = max(r.size - n_params, 1)
    inflation = r.size / effective_sample_size(r)
    cov = np.linalg.inv(jtj) * float(r @ r) / dof * inflation
    se = [*np.sqrt(np.abs(np.diag(cov))).tolist(), *([0.0] * (5 - n_params))]
    tau = float(p[4]) if n_params == 5 else 0.0
    y0, step_size, zeta, omega_n = (float(v) for v in p[:4])
    model = SecondOrderStep(y0, step_size, zeta, omega_n, tau, trial.t_step, tuple(se))
    command_step = trial.x_cmd - trial.zmp_commanded_before
    gain = model.step_size / command_step if command_step != 0.0 else None
    message = f"ζ = {model.zeta:.3g} ± {se[2]:.2g}, ω_n = {model.omega_n:.3g} ± {se[3]:.2g} rad/s"
    return TransientFit(True, message, metrics, model, gain, rms, noise)
