r"""Periodic offsets on the desired ZMP in walking direction (paper B §III.E, Figs. 11–13).

Paper B adds a half sine or a sawtooth to the desired ZMP, their frequency tied to the step
duration ``T`` [s] and their phase tuned by hand. With the step phase
:math:`u(t) = (t - t_0)/T - \varphi` (``t_0`` the start of the first step's weight transfer,
``varphi`` the phase [-], a fraction of a step) and ``frac`` the fractional part:

.. math::

    o_{hs}(t) = A \left(\sin(\pi\, \mathrm{frac}(u)) - \tfrac{2}{\pi}\right), \qquad
    o_{st}(t) = A\,(2\,\mathrm{frac}(u) - 1), \qquad
    o_{F}(t) = \sum_{k=1}^{K} a_k \cos(2\pi k u) + b_k \sin(2\pi k u).

The half sine is one half wave of height ``A`` [m] per step, its mean over a step removed
(so it reshapes the ZMP within a step instead of shifting the whole walk); the sawtooth ramps from
``-A`` to ``A`` over each step; the Fourier offset is the general periodic shape (``K``
harmonics of the step frequency, coefficients [m]). Every shape has the period ``T``. The
offset acts only while the robot walks: a raised-cosine envelope fades it in over the first
step and out over the last one, so the standing phases keep the linear reference. It points
along the torso's heading (world x for a straight walk).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.walking.pattern import WalkingPattern

__all__ = [
    "HALF_SINE_MEAN",
    "OFFSET_SHAPES",
    "OffsetParameters",
    "fourier_wave",
    "half_sine_wave",
    "offset_in_world",
    "periodic_wave",
    "sawtooth_wave",
    "walking_envelope",
]

OFFSET_SHAPES: tuple[str, ...] = ("half-sine", "sawtooth", "fourier")
"""Shapes of :class:`OffsetParameters`."""
HALF_SINE_MEAN = 2.0 / np.pi
"""Mean of ``sin(pi u)`` over ``u`` in [0, 1) [-]."""


@dataclass(frozen=True)
class OffsetParameters:
    """One periodic offset.

    Attributes:
        shape: one of :data:`OFFSET_SHAPES`.
        amplitude_m: A of the half sine or sawtooth [m] (may be negative).
        phase: phi, the shift of the wave in fractions of a step [-].
        fourier_m: (a_1, b_1, a_2, b_2, ...) of the Fourier shape [m].
        reference_speed_mps: the speed the offset was tuned at [m/s]; a walk at speed v gets
            the offset scaled by v / reference_speed_mps (the LIPM-vs-multibody ZMP error
            grows with the step length). 0 disables the scaling.
    """

    shape: str = "half-sine"
    amplitude_m: float = 0.0
    phase: float = 0.0
    fourier_m: tuple[float, ...] = ()
    reference_speed_mps: float = 0.0

    def __post_init__(self) -> None:
        if self.shape not in OFFSET_SHAPES:
            raise ParameterError(
                f"offset shape must be one of {', '.join(OFFSET_SHAPES)}; got {self.shape!r}"
            )
        values = (self.amplitude_m, self.phase, self.reference_speed_mps, *self.fourier_m)
        if not np.all(np.isfinite(values)):
            raise ParameterError(f"offset parameters must be finite; got {values}")
        if len(self.fourier_m) % 2:
            raise ParameterError(
                f"fourier_m holds (a_k, b_k) pairs; got {len(self.fourier_m)} values"
            )

    def as_dict(self) -> dict[str, object]:
        """JSON-ready parameters."""
        return {
            "shape": self.shape,
            "amplitude_m": self.amplitude_m,
            "phase": self.phase,
            "fourier_m": list(self.fourier_m),
            "reference_speed_mps": self.reference_speed_mps,
        }


FloatArray: TypeAlias = NDArray[np.float64]
"""Times [s] or a wave's values [m], per sample."""


def _step_phase(
    time_s: NDArray[np.float64], step_s: float, start_s: float, phase: float
) -> NDArray[np.float64]:
    """Steps since ``start_s`` [s] at ``time_s`` [s], less ``phase`` [steps]."""
    if not step_s > 0.0:
        raise ParameterError(f"step duration must be > 0 s; got {step_s}")
    return (np.asarray(time_s, dtype=np.float64) - start_s) / step_s - phase


def half_sine_wave(
    time_s: FloatArray, step_s: float, amplitude_m: float, phase: float, start_s: float = 0.0
) -> FloatArray:
    """One half sine of height ``amplitude_m`` [m] per step of ``step_s`` [s], zero mean."""
    u = _step_phase(time_s, step_s, start_s, phase)
    return amplitude_m * (np.sin(np.pi * (u - np.floor(u))) - HALF_SINE_MEAN)


def sawtooth_wave(
    time_s: FloatArray, step_s: float, amplitude_m: float, phase: float, start_s: float = 0.0
) -> FloatArray:
    """A ramp from ``-amplitude_m`` to ``amplitude_m`` [m] over each step of ``step_s`` [s]."""
    u = _step_phase(time_s, step_s, start_s, phase)
    return amplitude_m * (2.0 * (u - np.floor(u)) - 1.0)


def fourier_wave(
    time_s: FloatArray, step_s: float, coefficients_m: tuple[float, ...], start_s: float = 0.0
) -> FloatArray:
    """``sum_k a_k cos(2 pi k u) + b_k sin(2 pi k u)`` [m], u the step phase (no shift)."""
    u = _step_phase(time_s, step_s, start_s, 0.0)
    wave = np.zeros_like(u)
    for k in range(len(coefficients_m) // 2):
        angle = 2.0 * np.pi * (k + 1) * u
        wave += coefficients_m[2 * k] * np.cos(angle) + coefficients_m[2 * k + 1] * np.sin(angle)
    return wave


def periodic_wave(
    params: OffsetParameters, time_s: NDArray[np.float64], step_s: float, start_s: float = 0.0
) -> NDArray[np.float64]:
    """The wave of ``params`` on ``time_s`` [m] (no envelope)."""
    if params.shape == "half-sine":
        return half_sine_wave(time_s, step_s, params.amplitude_m, params.phase, start_s)
    if params.shape == "sawtooth":
        return sawtooth_wave(time_s, step_s, params.amplitude_m, params.phase, start_s)
    return fourier_wave(time_s, step_s, params.fourier_m, start_s)


def walking_envelope(
    time_s: NDArray[np.float64], start_s: float, end_s: float, fade_s: float
) -> NDArray[np.float64]:
    """1 between ``start_s + fade_s`` and ``end_s - fade_s``, raised-cosine fades, 0 outside."""
    t = np.asarray(time_s, dtype=np.float64)
    rise = np.clip((t - start_s) / fade_s, 0.0, 1.0)
    fall = np.clip((end_s - t) / fade_s, 0.0, 1.0)
    return 0.25 * (1.0 - np.cos(np.pi * rise)) * (1.0 - np.cos(np.pi * fall))


def offset_in_world(params: OffsetParameters, pattern: WalkingPattern) -> NDArray[np.float64]:
    """The offset of ``params`` for ``pattern``'s walk, along the torso heading [m], (N, 2).

    Pass it as ``zmp_offset`` to :func:`~zmpkit.walking.pattern.generate_pattern` with the
    same configuration.
    """
    plan = pattern.footsteps
    step_s = plan.gait.step_duration_s
    start_s, end_s = plan.walk_start_s, plan.steps[-1].t_end
    time = pattern.time_s
    wave = periodic_wave(params, time, step_s, start_s)
    wave *= walking_envelope(time, start_s, end_s, step_s)
    if params.reference_speed_mps > 0.0:
        wave *= abs(pattern.config.command.v_x) / params.reference_speed_mps
    yaw = pattern.feet.torso_yaw_in_world
    return np.column_stack([wave * np.cos(yaw), wave * np.sin(yaw)])
