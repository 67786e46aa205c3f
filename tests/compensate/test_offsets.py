"""Offset shapes: period tied to the step, amplitude, zero mean, envelope; parameter errors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.compensate.offsets import (
    OffsetParameters,
    fourier_wave,
    half_sine_wave,
    offset_in_world,
    sawtooth_wave,
)
from zmpkit.errors import ParameterError
from zmpkit.walking import PatternConfig, generate_pattern

step = st.floats(0.2, 1.0)
amplitude = st.floats(-0.05, 0.05).filter(lambda a: abs(a) > 1e-4)
phase = st.floats(0.0, 1.0)


def _even(values: list[float]) -> bool:
    return len(values) % 2 == 0


def _grid(step_s: float) -> np.ndarray:
    return np.linspace(0.0, 3 * step_s, 30001)


@settings(max_examples=40, deadline=None)
@given(step, amplitude, phase)
def test_half_sine_has_the_step_period_and_height(step_s, amplitude_m, ph) -> None:
    t = _grid(step_s)
    wave = half_sine_wave(t, step_s, amplitude_m, ph)
    np.testing.assert_allclose(half_sine_wave(t + step_s, step_s, amplitude_m, ph), wave,
                               atol=1e-9)  # fmt: skip
    # The grid (du = 1e-4 step) may miss the cusp where the sine restarts by up to du/2,
    # i.e. sample sin(pi u) >= pi du / 2 there, and the crest by du/2, i.e. sample
    # 1 - cos(pi du / 2) below 1: the sampled height is short of A by at most their sum.
    du = 1e-4
    grid_error = np.pi * du / 2 + (1.0 - np.cos(np.pi * du / 2))
    assert np.ptp(wave) <= abs(amplitude_m) * (1.0 + 1e-12)
    assert np.ptp(wave) >= abs(amplitude_m) * (1.0 - grid_error - 1e-12)  # + float rounding
    one_step = t < step_s
    assert np.mean(wave[one_step]) == pytest.approx(0.0, abs=1e-3 * abs(amplitude_m))


@settings(max_examples=40, deadline=None)
@given(step, amplitude, phase)
def test_sawtooth_has_the_step_period_and_amplitude(step_s, amplitude_m, ph) -> None:
    t = _grid(step_s)
    wave = sawtooth_wave(t, step_s, amplitude_m, ph)
    later = sawtooth_wave(t + step_s, step_s, amplitude_m, ph)
    away_from_jumps = np.abs(wave) < 0.999 * abs(amplitude_m)  # rounding picks a side there
    np.testing.assert_allclose(later[away_from_jumps], wave[away_from_jumps], atol=1e-9)
    assert np.max(np.abs(wave)) == pytest.approx(abs(amplitude_m), rel=1e-3)


@settings(max_examples=30, deadline=None)
@given(step, st.lists(st.floats(-0.02, 0.02), min_size=2, max_size=6).filter(_even))
def test_fourier_wave_has_the_step_period_and_its_coefficients(step_s, coefficients) -> None:
    t = np.arange(4000) * step_s / 1000  # four steps, 1000 samples each
    wave = fourier_wave(t, step_s, tuple(coefficients))
    np.testing.assert_allclose(fourier_wave(t + step_s, step_s, tuple(coefficients)), wave,
                               atol=1e-9)  # fmt: skip
    spectrum = np.fft.rfft(wave) / t.size * 2
    for k in range(len(coefficients) // 2):
        assert spectrum[4 * (k + 1)].real == pytest.approx(coefficients[2 * k], abs=1e-9)
        assert -spectrum[4 * (k + 1)].imag == pytest.approx(coefficients[2 * k + 1], abs=1e-9)


def test_offset_acts_only_while_walking_and_along_the_heading() -> None:
    pattern = generate_pattern(PatternConfig(duration_s=4.0))
    offset = offset_in_world(OffsetParameters("sawtooth", 0.01, 0.3), pattern)
    plan = pattern.footsteps
    t = pattern.time_s
    assert np.all(offset[t <= plan.walk_start_s] == 0.0)
    assert np.all(offset[t >= plan.steps[-1].t_end] == 0.0)
    assert np.all(offset[:, 1] == 0.0)
    assert np.max(np.abs(offset[:, 0])) == pytest.approx(0.01, rel=0.02)


def test_offset_scales_with_speed_from_its_reference_speed() -> None:
    slow = generate_pattern(PatternConfig(duration_s=4.0))
    params = OffsetParameters("half-sine", 0.01, 0.0, reference_speed_mps=0.1)
    scaled = offset_in_world(params, slow)  # default pattern walks at 0.2 m/s
    plain = offset_in_world(OffsetParameters("half-sine", 0.01, 0.0), slow)
    np.testing.assert_allclose(scaled, 2.0 * plain)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [({"shape": "sq"}, "offset shape must be one of half-sine, sawtooth, fourier; got 'sq"),
     ({"amplitude_m": float("nan")}, "offset parameters must be finite"),
     ({"shape": "fourier", "fourier_m": (0.1,)}, "fourier_m holds \\(a_k, b_k\\) pairs; got 1")],
)  # fmt: skip
def test_bad_parameters_are_named(kwargs, match) -> None:
    with pytest.raises(ParameterError, match=match):
        OffsetParameters(**kwargs)
