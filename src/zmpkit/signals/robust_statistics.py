"""Statistics of noisy, autocorrelated records: robust spread, effective sample size.

A step trial's ZMP is sampled much faster than its noise decorrelates, and it drifts; the
spread is taken about a line (:func:`robust_sigma`) and a mean's standard error uses the
effective number of independent samples (:func:`effective_sample_size`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite_array

__all__ = ["MAD_TO_SIGMA", "effective_sample_size", "robust_sigma"]

FloatArray = NDArray[np.float64]


MAD_TO_SIGMA = 1.4826
"""Scale from the median absolute deviation to the standard deviation of a Gaussian [-]."""


def effective_sample_size(residuals: ArrayLike) -> float:
    r"""Effective number of independent samples in an autocorrelated series.

    .. math:: n_{eff} = \frac{n}{1 + 2\sum_{k=1}^{K}\rho_k}

    with the sample autocorrelation :math:`\rho_k` summed up to the last lag before the
    first non-positive one (initial positive sequence), clipped to [1, n].

    Args:
        residuals: the series minus its mean (or model) [any unit], shape (n,).
    """
    r = finite_array("residuals", residuals, (None,))
    n = r.size
    if n < 3:
        return float(n)
    r = r - r.mean()
    spectrum = np.fft.rfft(r, 2 * n)
    acov = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    if acov[0] <= 0.0:
        return float(n)
    rho = acov[1:] / acov[0]
    stop = np.flatnonzero(rho <= 0.0)
    tau = 1.0 + 2.0 * float(np.sum(rho[: stop[0] if stop.size else rho.size]))
    return float(min(max(n / tau, 1.0), n))


def robust_sigma(t: FloatArray, y: FloatArray) -> float:
    """1.4826 MAD of ``y`` about its least-squares line in ``t``: the noise, not the drift.

    Args:
        t: sample times [s], shape (n,).
        y: the samples [any unit], shape (n,); fewer than 3 give 0.

    Returns:
        The noise's standard deviation [unit of ``y``].
    """
    if y.size < 3:
        return 0.0
    residual = y - np.polyval(np.polyfit(t, y, 1), t)
    return MAD_TO_SIGMA * float(np.median(np.abs(residual - np.median(residual))))
