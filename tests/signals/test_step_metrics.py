"""Tests of zmpkit.signals.step_metrics against closed forms and control.step_info."""

from __future__ import annotations

import math

import control
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.signals.step_metrics import StepMetrics, step_metrics

SAMPLES = 6001


def _second_order(omega_n: float, zeta: float) -> tuple[control.TransferFunction, np.ndarray]:
    """ω_n²/(s² + 2ζω_n s + ω_n²) and a grid long enough for e^{−ζω_n t} to reach e^{−30}."""
    sys = control.tf([omega_n**2], [1.0, 2.0 * zeta * omega_n, omega_n**2])
    return sys, np.linspace(0.0, 30.0 / (zeta * omega_n), SAMPLES)


second_order_params = {"omega_n": st.floats(0.5, 20.0), "zeta": st.floats(0.11, 0.94)}


@settings(max_examples=25, deadline=None)
@given(**second_order_params)
@pytest.mark.slow
def test_second_order_overshoot_and_peak_time_are_analytic(omega_n: float, zeta: float) -> None:
    sys, t = _second_order(omega_n, zeta)
    metrics = step_metrics(t, control.step_response(sys, t).outputs)
    dt, root = t[1] - t[0], math.sqrt(1.0 - zeta**2)
    # sampling the peak misses it by at most max|y''| dt²/8, and |y''| <= ω_n²/√(1−ζ²)
    sampling_pct = 100.0 * omega_n**2 * dt**2 / (8.0 * root) + 1e-9
    assert metrics.final_value == pytest.approx(1.0, abs=1e-11)
    assert metrics.overshoot_pct == pytest.approx(
        100.0 * math.exp(-zeta * math.pi / root), abs=sampling_pct
    )
    assert metrics.peak_time_s == pytest.approx(math.pi / (omega_n * root), abs=dt)


@settings(max_examples=25, deadline=None)
@given(**second_order_params)
@pytest.mark.slow
def test_second_order_agrees_with_control_step_info(omega_n: float, zeta: float) -> None:
    sys, t = _second_order(omega_n, zeta)
    info = control.step_info(sys, t)
    metrics = step_metrics(t, control.step_response(sys, t).outputs, final_value=1.0)
    dt = t[1] - t[0]
    assert metrics.overshoot_pct == pytest.approx(info["Overshoot"], rel=1e-12)
    assert metrics.peak_value == pytest.approx(info["Peak"], rel=1e-12)
    assert metrics.peak_time_s == pytest.approx(info["PeakTime"], abs=1e-12)
    # step_info takes sample times, we interpolate the crossings: within one sample
    assert metrics.rise_time_s == pytest.approx(info["RiseTime"], abs=dt)
    assert metrics.settling_time_s == pytest.approx(info["SettlingTime"], abs=dt)


def test_first_order_rise_and_settling_times_are_analytic() -> None:
    tau = 0.4
    t = np.linspace(0.0, 15.0 * tau, 30001)
    y = 1.0 - np.exp(-t / tau)
    dt = t[1] - t[0]
    interp = dt**2 / tau  # linear interpolation error bound of the crossing times
    metrics = step_metrics(t, y, final_value=1.0)
    assert metrics.overshoot_pct == 0.0
    assert metrics.rise_time_s == pytest.approx(tau * math.log(9.0), abs=interp)
    assert metrics.settling_time_s == pytest.approx(tau * math.log(50.0), abs=interp)
    custom = step_metrics(t, y, final_value=1.0, rise_limits=(0.05, 0.95), settling_band=0.05)
    assert custom.rise_time_s == pytest.approx(tau * math.log(19.0), abs=interp)
    assert custom.settling_time_s == pytest.approx(tau * math.log(20.0), abs=interp)


def test_negative_step_mirrors_positive_step() -> None:
    sys, t = _second_order(3.0, 0.3)
    y = control.step_response(sys, t).outputs
    up = step_metrics(t, 0.02 + 0.09 * y)
    down = step_metrics(t, 0.02 - 0.09 * y)
    assert down.step_size == pytest.approx(-up.step_size, rel=1e-12)
    assert down.initial_value == pytest.approx(0.02, rel=1e-12)
    assert down.peak_value == pytest.approx(0.04 - up.peak_value, rel=1e-12)
    for name in ("overshoot_pct", "peak_time_s", "rise_time_s", "settling_time_s"):
        assert getattr(down, name) == pytest.approx(getattr(up, name), rel=1e-9)


def test_delayed_step_measures_times_from_t_step() -> None:
    sys, t = _second_order(4.0, 0.5)
    y = control.step_response(sys, t).outputs
    t_shifted = np.concatenate([np.linspace(0.0, 1.0, 100, endpoint=False), 1.0 + t])
    y_shifted = np.concatenate([np.zeros(100), y])
    plain = step_metrics(t, y)
    delayed = step_metrics(t_shifted, y_shifted, t_step=1.0)
    for name in ("overshoot_pct", "peak_time_s", "rise_time_s", "settling_time_s"):
        assert getattr(delayed, name) == pytest.approx(getattr(plain, name), rel=1e-9)


def test_steady_state_error_as_in_paper_table_1() -> None:
    # paper A Table 1, LIPM at ZMP_ref = 0.10 m: ZMP_FT = 0.1116 m, 11.6 % error
    t = np.linspace(0.0, 5.0, 501)
    metrics = step_metrics(t, np.where(t > 0.5, 0.1116, 0.0), reference=0.10)
    assert metrics.final_value == pytest.approx(0.1116, rel=1e-12)
    assert metrics.steady_state_error == pytest.approx(-0.0116, rel=1e-9)
    assert metrics.steady_state_error_pct == pytest.approx(-11.6, rel=1e-9)


def test_steady_state_error_pct_is_none_for_zero_or_missing_reference() -> None:
    t = np.linspace(0.0, 1.0, 11)
    at_zero = step_metrics(t, np.full(11, 5e-5), reference=0.0)
    assert at_zero.steady_state_error == pytest.approx(-5e-5)
    assert at_zero.steady_state_error_pct is None
    no_ref = step_metrics(t, t)
    assert no_ref.steady_state_error is None
    assert no_ref.steady_state_error_pct is None


def test_zero_step_leaves_step_quantities_undefined() -> None:
    metrics = step_metrics(np.linspace(0.0, 1.0, 11), np.full(11, 0.3))
    assert metrics.step_size == 0.0
    assert metrics.overshoot_pct is None
    assert metrics.rise_time_s is None
    assert metrics.settling_time_s is None
    assert metrics.peak_value == 0.3


def test_response_that_never_settles_or_rises_gives_none() -> None:
    t = np.linspace(0.0, 10.0, 1001)
    ringing = 1.0 - np.cos(2.0 * np.pi * t)  # never decays
    metrics = step_metrics(t, ringing, final_value=1.0)
    assert metrics.settling_time_s is None
    short = step_metrics(t, 0.5 * (1.0 - np.exp(-t)), final_value=1.0)
    assert short.rise_time_s is None
    assert short.settling_time_s is None


def test_default_final_value_is_mean_of_last_ten_percent_or_window() -> None:
    t = np.linspace(0.0, 9.9, 100)
    y = np.arange(100.0)
    assert step_metrics(t, y).final_value == pytest.approx(np.mean(y[-10:]))
    # the window [9.45, 9.9] s holds samples 95 … 99
    assert step_metrics(t, y, steady_window_s=0.45).final_value == pytest.approx(97.0)


@settings(max_examples=50, deadline=None)
@given(
    y=st.lists(st.floats(-1e3, 1e3, allow_subnormal=False), min_size=2, max_size=40),
    band=st.floats(0.001, 0.5),
)
def test_never_returns_nan(y: list[float], band: float) -> None:
    metrics = step_metrics(np.arange(len(y), dtype=float), y, settling_band=band, reference=1.0)
    for name in StepMetrics.__dataclass_fields__:
        value = getattr(metrics, name)
        assert value is None or np.all(np.isfinite(value)), name


def test_a_step_too_small_for_a_percentage_has_no_overshoot() -> None:
    """Found by hypothesis: a step of -2.2e-308 under a peak 1 away overflowed to inf %."""
    metrics = step_metrics(np.arange(3.0), [0.0, -1.0, -2.2250738585072014e-308], reference=1.0)
    assert metrics.overshoot_pct is None


def test_lengths_must_match() -> None:
    with pytest.raises(ParameterError, match=r"t and y must have the same length, got 3 and 2"):
        step_metrics([0.0, 1.0, 2.0], [0.0, 1.0])


def test_time_must_increase() -> None:
    with pytest.raises(ParameterError, match=r"t must be strictly increasing, but t\[2\] = 0.5"):
        step_metrics([0.0, 1.0, 0.5], [0.0, 1.0, 1.0])


def test_nan_in_response_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"y must be finite everywhere, got non-finite"):
        step_metrics([0.0, 1.0, 2.0], [0.0, float("nan"), 1.0])


def test_t_step_outside_the_record_is_rejected() -> None:
    with pytest.raises(ParameterError, match=r"t_step must lie in \[t\[0\], t\[-1\]\)"):
        step_metrics([0.0, 1.0, 2.0], [0.0, 1.0, 1.0], t_step=2.0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"settling_band": 0.0}, r"settling_band must lie in \(0, 1\)"),
        ({"rise_limits": (0.9, 0.1)}, r"rise_limits must satisfy 0 <= lower < upper <= 1"),
        ({"steady_window_s": -1.0}, r"steady_window_s must be > 0 s, got -1.0 s"),
    ],
)
def test_bad_options_are_rejected(kwargs: dict[str, object], message: str) -> None:
    with pytest.raises(ParameterError, match=message):
        step_metrics([0.0, 1.0, 2.0], [0.0, 1.0, 1.0], **kwargs)
