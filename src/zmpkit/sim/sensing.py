r"""The sensor effects (S): what a real F-T sensor, encoder and IMU make of the true values.

An F-T sample, taken every ``1 / ft_rate_hz`` seconds, is

.. math::
    y_k = Q\big(y_{k-1} + \alpha\,((1 + g) \circ w_k + o + \dot o\,t_k + n_k - y_{k-1})\big),
    \qquad \alpha = 1 - e^{-2 \pi f_c / f_s},

with gain error ``g`` (per axis), offset ``o``, an offset drift at the rate :math:`\dot o`
(drawn once per sensor from its stream when the truth gives a drift, :math:`t_k = k / f_s`
the time since the sensor started), white noise ``n_k`` and a first-order low-pass filter
(cutoff ``f_c``); ``Q`` rounds to the output quantum (applied to the output, the filter
state stays continuous). Noise comes from numpy Generators seeded per stream, so the same
seed gives identical readings.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from zmpkit.sim.sensor_errors import SensorParams

__all__ = ["FtChannel", "quantise", "sample_series"]


def quantise(value: NDArray[np.float64], step: NDArray[np.float64]) -> NDArray[np.float64]:
    """Round each element to a multiple of its ``step``; a step of 0 leaves it exact."""
    safe = np.where(step > 0.0, step, 1.0)
    return np.where(step > 0.0, np.round(value / safe) * safe, value)


class FtChannel:
    """One 6-axis F-T sensor with offset, gain error, noise, low-pass filter and quantisation.

    Args:
        params: the sensor errors.
        offset: this sensor's offset (Fx, Fy, Fz, Tx, Ty, Tz) [N, N·m].
        rng: the Generator of this sensor's noise (and of its drift rate).
        gain_error: this sensor's relative gain error per axis [-]; None: ``params``'s on
            every axis.
    """

    def __init__(
        self,
        params: SensorParams,
        offset: Sequence[float],
        rng: np.random.Generator,
        gain_error: Sequence[float] | None = None,
    ) -> None:
        gain = (params.ft_gain_error,) * 6 if gain_error is None else gain_error
        self._gain = 1.0 + np.asarray(gain, dtype=np.float64)
        self._offset = np.asarray(offset, dtype=np.float64)
        drift_std, self._noise, self._quantum, self._alpha = _channel_constants(params)
        drift = drift_std * rng.standard_normal(6) if drift_std is not None else np.zeros(6)
        self._drift_step = drift / params.ft_rate_hz  # offset change per sample [N, N·m]
        self._count = 0
        self._rng = rng
        self._state: NDArray[np.float64] | None = None
        self.output = np.zeros(6)

    def sample(self, wrench_true: NDArray[np.float64]) -> NDArray[np.float64]:
        """Take one sample of the true wrench [N, N·m] and return the measured one."""
        offset = self._offset + self._drift_step * float(self._count)
        self._count += 1
        raw = self._gain * wrench_true + offset + self._noise * self._rng.standard_normal(6)
        if self._state is None:
            self._state = raw
        else:
            self._state = self._state + self._alpha * (raw - self._state)
        self.output = quantise(self._state, self._quantum)
        return self.output


@lru_cache(maxsize=64)
def _channel_constants(
    params: SensorParams,
) -> tuple[NDArray[np.float64] | None, NDArray[np.float64], NDArray[np.float64], float]:
    """A channel's constants of ``params``, shared by its channels (read-only arrays).

    The drift rate's std [N/s, N·m/s] (None: no drift), the noise std [N, N·m], the output
    quantum [N, N·m] and the filter factor ``alpha`` [-].
    """
    drift_std = np.asarray(params.ft_offset_drift_std, dtype=np.float64)
    noise = np.asarray(params.ft_noise_std, dtype=np.float64)
    quantum = np.asarray(params.ft_quantisation, dtype=np.float64)
    cutoff, rate = params.ft_cutoff_hz, params.ft_rate_hz
    alpha = 1.0 - math.exp(-2.0 * math.pi * cutoff / rate) if cutoff > 0 else 1.0
    for array in (drift_std, noise, quantum):
        array.flags.writeable = False
    return (drift_std if np.any(drift_std) else None), noise, quantum, alpha


def sample_series(
    channels: Sequence[FtChannel], wrenches_true: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Samples of many channels over a series of true wrenches, advancing each channel.

    The same numbers as ``[[c.sample(w) for w in series] for c, series in ...]`` (the same
    noise draws and the same arithmetic, element by element), with the loop over channels
    done by numpy: the F-T readings of a batch of rollouts.

    Args:
        channels: C channels.
        wrenches_true: true wrenches [N, N·m], shape (C, n, 6).

    Returns:
        The measured wrenches, shape (C, n, 6); each channel's ``output`` is its last row.
    """
    wrenches_true = np.asarray(wrenches_true, dtype=np.float64)
    n = wrenches_true.shape[1]
    out = np.empty_like(wrenches_true)
    if n == 0:
        return out
    gain = np.array([c._gain for c in channels])
    offset = np.array([c._offset for c in channels])
    drift = np.array([c._drift_step for c in channels])
    count = np.array([[float(c._count)] for c in channels])
    noise = np.array([c._noise * np.ones(6) for c in channels])
    quantum = np.array([c._quantum * np.ones(6) for c in channels])
    alpha = np.array([[c._alpha] for c in channels])
    draws = np.stack([c._rng.standard_normal((n, 6)) for c in channels])
    fresh = np.array([c._state is None for c in channels])
    state = np.array([np.zeros(6) if c._state is None else c._state for c in channels])
    for k in range(n):
        raw = (
            gain * wrenches_true[:, k] + (offset + drift * (count + float(k))) + noise * draws[:, k]
        )
        state = np.where(fresh[:, None], raw, state + alpha * (raw - state))
        fresh[:] = False
        out[:, k] = quantise(state, quantum)
    for i, c in enumerate(channels):
        c._count += n
        c._state = state[i].copy()
        c.output = out[i, -1].copy()
    return out
