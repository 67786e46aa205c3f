"""Tests of zmpkit.identify on synthetic step trials with a known error model and transient."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import InputFileError, ModelError, ParameterError
from zmpkit.identify import (
    BalanceParams,
    ErrorModel,
    PlaneParams,
    fit_error_model,
    fit_transient,
    identify_balance,
    second_order_step,
)
from zmpkit.identify.error_fit import SCATTER_FLOOR_M
from zmpkit.signals import StepTrial, effective_sample_size, steady_state

PAPER_A = ErrorModel("quadratic", (0.834, 1.024, -0.0004))  # paper A eq. 13
TEO_MASS_KG, TEO_LENGTH_M = 62.6, 0.893  # paper A §4.1
TARGETS_M = np.round(np.arange(0.0, 0.1001, 0.01), 2)  # paper A Table 1
NOISE_M = 3e-4  # per-sample ZMP noise [m]


def synthetic_trial(
    model: ErrorModel,
    x_cmd: float,
    rng: np.random.Generator,
    *,
    zeta: float = 0.3,
    omega_n: float = 6.0,
    dead_time: float = 0.04,
    noise: float = NOISE_M,
    drift_m_per_s: float = 0.0,
    duration_s: float = 6.0,
    plane: str = "sagittal",
) -> tuple[StepTrial, np.ndarray]:
    """A step at t = 1 s from f(0) to f(x_cmd) as a 2nd-order response; also the clean signal."""
    t = np.arange(0.0, 1.0 + duration_s, 0.01)
    y0, y1 = float(model.predict(0.0)), float(model.predict(x_cmd))
    clean = y0 + (y1 - y0) * second_order_step(t - 1.0 - dead_time, zeta, omega_n)
    clean = clean + drift_m_per_s * np.maximum(t - 1.0, 0.0)
    trial = StepTrial(t, clean + rng.normal(0.0, noise, t.size), x_cmd, 1.0, plane)
    return trial, clean


# --- steady state ----------------------------------------------------------------------------


def test_steady_state_of_a_noisy_step_excludes_the_transient() -> None:
    rng = np.random.default_rng(1)
    trial, _ = synthetic_trial(PAPER_A, 0.08, rng)
    result = steady_state(trial)
    truth = float(PAPER_A.predict(0.08))
    # envelope e^{-ζ ω_n t} of the oscillation (0.0149 m step) falls below 4σ = 1.2 mm at ~1.4 s
    assert result.settled
    assert 1.0 + 1.0 < result.window[0] < 1.0 + 3.0
    assert abs(result.value - truth) < 3.0 * result.std_error
    naive = NOISE_M / math.sqrt(result.n_samples)
    assert result.std_error == pytest.approx(naive, rel=0.35)  # white noise: n_eff ≈ n


def test_steady_state_with_slow_drift_is_honest_when_the_creep_check_is_off() -> None:
    rng = np.random.default_rng(2)
    trial, clean = synthetic_trial(PAPER_A, 0.05, rng, drift_m_per_s=1e-4, duration_s=8.0)
    result = steady_state(trial, creep_horizon_s=None)
    inside = (trial.time >= result.window[0]) & (trial.time <= result.window[1])
    assert result.settled
    assert result.drift_rate == pytest.approx(1e-4, rel=0.3)
    assert abs(result.value - clean[inside].mean()) < 3.0 * result.std_error
    assert result.std_error > 2.0 * NOISE_M / math.sqrt(result.n_samples)  # drift is correlated


def test_a_creep_beyond_tolerance_is_drifting_with_its_rate() -> None:
    # 0.1 mm/s moves the ZMP 1 mm in the 10 s creep horizon: 2 % of a 0.05 m step, beyond
    # the 0.5 % tolerance; a creep of 0.01 mm/s (0.1 mm, inside the 0.2 mm floor) is not
    rng = np.random.default_rng(2)
    trial, _ = synthetic_trial(PAPER_A, 0.05, rng, drift_m_per_s=1e-4, duration_s=8.0)
    result = steady_state(trial)
    assert not result.settled
    assert result.status == "drifting"
    assert result.value is None
    assert result.drift_rate_mm_s == pytest.approx(0.1, rel=0.3)
    assert "still creeps at" in result.reason
    slow, _ = synthetic_trial(PAPER_A, 0.05, rng, drift_m_per_s=1e-5, duration_s=8.0)
    assert steady_state(slow).settled


def test_a_ramp_that_never_enters_the_band_is_drifting_not_oscillating() -> None:
    rng = np.random.default_rng(5)
    trial, _ = synthetic_trial(PAPER_A, 0.05, rng, drift_m_per_s=2e-3, duration_s=8.0)
    result = steady_state(trial)
    assert (result.settled, result.status) == (False, "drifting")
    assert result.drift_rate_mm_s == pytest.approx(2.0, rel=0.1)


def test_persistent_oscillation_is_not_settled() -> None:
    rng = np.random.default_rng(3)
    trial, _ = synthetic_trial(PAPER_A, 0.06, rng, zeta=0.02)
    result = steady_state(trial)
    assert not result.settled
    assert result.value is None
    assert result.std_error is None
    assert "oscillation that has not died out" in result.reason
    assert result.status == "oscillating"


def test_short_hold_is_not_settled() -> None:
    rng = np.random.default_rng(4)
    trial, _ = synthetic_trial(PAPER_A, 0.06, rng, duration_s=0.6)
    result = steady_state(trial)
    assert not result.settled
    assert result.value is None
    assert "of its final median for only" in result.reason
    assert result.status == "short"


def test_effective_sample_size_of_white_and_ar1_noise() -> None:
    rng = np.random.default_rng(5)
    white = rng.normal(size=20_000)
    assert effective_sample_size(white) == pytest.approx(20_000, rel=0.1)
    phi, ar = 0.9, np.zeros(20_000)
    for k in range(1, ar.size):
        ar[k] = phi * ar[k - 1] + white[k]
    # closed form for AR(1): n (1 - φ) / (1 + φ)
    assert effective_sample_size(ar) == pytest.approx(20_000 * (1 - phi) / (1 + phi), rel=0.3)


# --- error model -----------------------------------------------------------------------------

# b²/(4|a|) >= 0.053 m: the turning point lies beyond every target in ±0.04 m (c <= 0.01 m)
coefficients = st.tuples(st.floats(-3.0, 3.0), st.floats(0.8, 1.5), st.floats(-0.01, 0.01))


@settings(max_examples=80, deadline=None)
@given(coef=coefficients, kind=st.sampled_from(["quadratic", "odd_quadratic"]))
def test_invert_is_the_inverse_near_the_identity(coef: tuple, kind: str) -> None:
    model = ErrorModel(kind, coef)
    x = np.linspace(-0.04, 0.04, 41)
    u = model.invert(x)
    np.testing.assert_allclose(model.predict(u), x, rtol=0, atol=1e-15)
    assert np.all(model.derivative(u) > 0.0)  # the branch through the identity


def test_quadratic_inverse_is_finite_as_a_vanishes_and_at_the_offset() -> None:
    for a in (0.0, 1e-300, -1e-300, 1e-12):
        model = ErrorModel("quadratic", (a, 1.024, -0.0004))
        assert model.invert(0.05) == pytest.approx((0.05 + 0.0004) / 1.024, rel=1e-10)
    assert PAPER_A.invert(-0.0004) == 0.0


def test_cubic_inverse_by_brent() -> None:
    model = ErrorModel("cubic", (-5.0, 0.834, 1.024, -0.0004))
    x = np.linspace(-0.1, 0.1, 21)
    np.testing.assert_allclose(model.predict(model.invert(x)), x, rtol=0, atol=1e-15)


def test_invert_outside_the_monotonic_range_names_the_range() -> None:
    model = ErrorModel("quadratic", (-5.0, 1.0, 0.0))  # turns at x_cmd = 0.1 m, x = 0.05 m
    with pytest.raises(ModelError, match=r"not monotonic beyond x_cmd = 0.1 m.*turns at 0.05 m"):
        model.invert([0.0, 0.06])
    cubic = ErrorModel("cubic", (-50.0, 0.834, 1.024, -0.0004))
    with pytest.raises(ModelError, match=r"requested targets span \[-0.1, 0.1\] m"):
        cubic.invert(np.linspace(-0.1, 0.1, 5))
    with pytest.raises(ModelError, match="slope b = -1 <= 0"):
        ErrorModel("linear", (-1.0, 0.0)).invert(0.01)


def test_error_model_rejects_bad_coefficients() -> None:
    with pytest.raises(ParameterError, match=r"kind must be one of \('linear', 'quadratic'"):
        ErrorModel("quartic", (1.0, 2.0))
    with pytest.raises(ParameterError, match=r"needs 3 coefficients \('a', 'b', 'c'\), got 2"):
        ErrorModel("quadratic", (1.0, 2.0))


# --- error fit -------------------------------------------------------------------------------


def test_fit_recovers_paper_coefficients_with_intervals_and_picks_quadratic() -> None:
    rng = np.random.default_rng(0)
    x = TARGETS_M
    y = PAPER_A.predict(x) + rng.normal(0.0, 2e-4, x.size)
    fit = fit_error_model(x, y, std_errors=np.full(x.size, 2e-4))
    assert fit.kind == "quadratic"
    assert "quadratic (LOO RMSE" in fit.reason
    assert "beats linear" in fit.reason
    for name, truth in PAPER_A.as_dict().items():
        low, high = fit.interval(name)
        assert low < truth < high, name
    assert fit.r_squared > 0.999
    np.testing.assert_allclose(fit.residuals, y - fit.predict(x), atol=1e-15)
    assert set(fit.loo_rmse) == {"linear", "quadratic", "odd_quadratic", "cubic"}


@pytest.mark.slow
def test_confidence_intervals_cover_the_truth_95_percent_of_the_time() -> None:
    hits, n_runs = np.zeros(3), 400
    for seed in range(n_runs):
        rng = np.random.default_rng(seed)
        y = PAPER_A.predict(TARGETS_M) + rng.normal(0.0, 2e-4, TARGETS_M.size)
        fit = fit_error_model(TARGETS_M, y, model="quadratic")
        hits += [fit.interval(n)[0] < v < fit.interval(n)[1] for n, v in PAPER_A.as_dict().items()]
    # binomial standard deviation at p = 0.95, n = 400: 1.1 %
    assert np.all((hits / n_runs > 0.91) & (hits / n_runs < 0.985))


@pytest.mark.slow
def test_cross_validation_picks_linear_for_linear_data() -> None:
    linear = ErrorModel("linear", (1.02, -0.0004))
    chosen = []
    for seed in range(200):
        rng = np.random.default_rng(seed)
        y = linear.predict(TARGETS_M) + rng.normal(0.0, 2e-4, TARGETS_M.size)
        chosen.append(fit_error_model(TARGETS_M, y).kind)
    assert chosen[0] == "linear"
    assert chosen.count("linear") / len(chosen) > 0.88  # ~94 % with the 20 % margin


@pytest.mark.slow
def test_cross_validation_picks_quadratic_for_quadratic_data() -> None:
    chosen = []
    for seed in range(200):
        rng = np.random.default_rng(seed)
        y = PAPER_A.predict(TARGETS_M) + rng.normal(0.0, 2e-4, TARGETS_M.size)
        chosen.append(fit_error_model(TARGETS_M, y).kind)
    assert chosen[0] == "quadratic"
    assert chosen.count("quadratic") / len(chosen) > 0.88  # ~95 %


def test_odd_quadratic_wins_on_symmetric_softening() -> None:
    truth = ErrorModel("odd_quadratic", (0.8, 1.0, 0.0))
    x = np.linspace(-0.1, 0.1, 21)
    y = truth.predict(x) + np.random.default_rng(7).normal(0.0, 2e-4, x.size)
    fit = fit_error_model(x, y)
    assert fit.kind == "odd_quadratic"
    assert fit.interval("a")[0] < 0.8 < fit.interval("a")[1]


def test_fit_error_texts() -> None:
    with pytest.raises(ParameterError, match="x_measured must have shape"):
        fit_error_model([0.0, 0.1, 0.2], [0.0, 0.1])
    with pytest.raises(ParameterError, match=r"std_errors must be > 0 m, got std_errors\[1\] = 0"):
        fit_error_model([0.0, 0.1, 0.2], [0.0, 0.1, 0.2], std_errors=[1e-3, 0.0, 1e-3])
    with pytest.raises(ParameterError, match=r"models must be among .*got \['spline'\]"):
        fit_error_model([0.0, 0.1, 0.2], [0.0, 0.1, 0.2], model="spline")
    with pytest.raises(ModelError, match="no candidate error model can be cross-validated"):
        fit_error_model([0.0, 0.1, 0.2], [0.0, 0.1, 0.2])
    with pytest.raises(ModelError, match="too few distinct commands"):
        fit_error_model([0.1] * 5, [0.1, 0.11, 0.09, 0.1, 0.1], model="linear")


# --- transient -------------------------------------------------------------------------------


def test_transient_fit_recovers_zeta_omega_and_dead_time() -> None:
    rng = np.random.default_rng(11)
    trial, _ = synthetic_trial(PAPER_A, 0.07, rng, zeta=0.3, omega_n=6.0, dead_time=0.04)
    fit = fit_transient(trial)
    assert fit.ok, fit.message
    model = fit.model
    for name, truth in (("zeta", 0.3), ("omega_n", 6.0), ("dead_time", 0.04)):
        value = getattr(model, name)
        assert abs(value - truth) < 4.0 * model.std_error(name), name
        assert value == pytest.approx(truth, rel=0.05), name
    expected_gain = (PAPER_A.predict(0.07) - PAPER_A.predict(0.0)) / 0.07
    assert fit.gain == pytest.approx(expected_gain, rel=0.01)
    # ζ = 0.3: overshoot 100 exp(-π ζ / sqrt(1 - ζ²)) = 37.2 %
    assert model.overshoot_pct == pytest.approx(37.2, abs=1.5)
    assert fit.overshoot_pct == pytest.approx(37.2, abs=5.0)
    assert 0.5 < fit.settling_time_s < 3.0


def test_transient_without_a_step_is_flagged_not_nan() -> None:
    rng = np.random.default_rng(12)
    trial, _ = synthetic_trial(PAPER_A, 0.0, rng)
    fit = fit_transient(trial)
    assert not fit.ok
    assert fit.zeta is None
    assert fit.model is None
    assert "no transient to fit" in fit.message


def test_a_step_at_the_end_of_the_record_is_flagged_not_a_traceback() -> None:
    """Half a sample recorded after the step: no ω_n both below Nyquist and with a period
    recorded (scipy refused the bounds with a ValueError before)."""
    t = np.arange(0.0, 1.0 + 1e-9, 0.01)
    y = np.where(t >= 0.999, 0.05, 0.0) + 1e-4 * np.random.default_rng(3).standard_normal(t.size)
    fit = fit_transient(StepTrial(t, y, 0.05, 0.995))
    assert not fit.ok
    assert fit.model is None
    assert fit.message.startswith("too little recorded after the step to fit: 0.005 s at a ")


def test_second_order_step_is_continuous_through_critical_damping() -> None:
    t = np.linspace(0.0, 3.0, 301)
    below, at, above = (second_order_step(t, z, 5.0) for z in (1 - 1e-7, 1.0, 1 + 1e-7))
    np.testing.assert_allclose(below, at, atol=1e-6)
    np.testing.assert_allclose(above, at, atol=1e-6)
    np.testing.assert_allclose(at, 1 - np.exp(-5 * t) * (1 + 5 * t), atol=1e-15)


# --- the whole identification ----------------------------------------------------------------


def synthetic_dataset(seed: int) -> list[StepTrial]:
    rng = np.random.default_rng(seed)
    frontal = ErrorModel("linear", (0.95, 0.001))
    trials = [synthetic_trial(PAPER_A, x, rng)[0] for x in TARGETS_M]
    trials += [synthetic_trial(frontal, x, rng, plane="frontal")[0] for x in TARGETS_M]
    return trials


def test_identify_balance_recovers_both_planes() -> None:
    result = identify_balance(synthetic_dataset(0), mass=TEO_MASS_KG, com_height=TEO_LENGTH_M)
    sagittal, frontal = result.planes["sagittal"], result.planes["frontal"]
    assert sagittal.error_fit.kind == "quadratic"
    assert frontal.error_fit.kind == "linear"
    for name, truth in PAPER_A.as_dict().items():
        low, high = sagittal.error_fit.interval(name)
        assert low < truth < high, name
    assert frontal.error_fit.interval("b")[0] < 0.95 < frontal.error_fit.interval("b")[1]
    params = result.params.plane("sagittal")
    assert params.zeta == pytest.approx(0.3, rel=0.05)
    assert params.omega_n == pytest.approx(6.0, rel=0.05)
    assert sagittal.excluded == ()
    assert sum(t.ok for t in sagittal.transients) == len(TARGETS_M) - 1  # not the 0 step


def test_identify_balance_reports_unsettled_trials() -> None:
    rng = np.random.default_rng(3)
    trials = [synthetic_trial(PAPER_A, x, rng)[0] for x in (0.02, 0.04)]
    trials.append(synthetic_trial(PAPER_A, 0.06, rng, zeta=0.02)[0])
    with pytest.raises(ModelError, match=r"sagittal plane has 2 settled trials.*trial 2"):
        identify_balance(trials, mass=TEO_MASS_KG, com_height=TEO_LENGTH_M)
    with pytest.raises(ParameterError, match="at least one StepTrial"):
        identify_balance([], mass=TEO_MASS_KG, com_height=TEO_LENGTH_M)


def test_step_trial_error_texts() -> None:
    t = np.arange(0.0, 1.0, 0.1)
    with pytest.raises(ParameterError, match=r"plane must be one of \('sagittal', 'frontal'\)"):
        StepTrial(t, np.zeros(t.size), 0.01, 0.5, "lateral")
    with pytest.raises(ParameterError, match=r"t_step must lie in \[time\[0\], time\[-1\]\)"):
        StepTrial(t, np.zeros(t.size), 0.01, 2.0)
    with pytest.raises(ParameterError, match=r"zmp_measured must have shape \(10\)"):
        StepTrial(t, np.zeros(3), 0.01, 0.5)


# --- parameters file -------------------------------------------------------------------------


def test_balance_params_yaml_round_trip(tmp_path: Path) -> None:
    params = BalanceParams(
        TEO_MASS_KG,
        TEO_LENGTH_M,
        {
            "sagittal": PlaneParams(PAPER_A, 0.31, 6.2),
            "frontal": PlaneParams(ErrorModel("cubic", (1.5, 0.2, 0.99, 1e-4)), None, None),
        },
    )
    path = params.to_yaml(tmp_path / "params.yaml")
    text = path.read_text()
    for key in ("mass_kg: 62.6", "com_height_m: 0.893", "a_per_m: 0.834", "c_m: -0.0004"):
        assert key in text
    loaded = BalanceParams.from_yaml(path)
    assert loaded.to_dict() == params.to_dict()
    assert loaded.plane("sagittal").error_model == PAPER_A


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (("pendulum", "mass_kg", -1.0), "field 'pendulum.mass_kg' must be > 0, got -1.0"),
        (("pendulum", "mass_kg", None), "field 'pendulum.mass_kg' is missing"),
        (("pendulum", "com_heigth_m", 0.9), "field 'pendulum' has unknown keys ['com_heigth_m']"),
        (("model", "model", "spline"), "field 'planes.sagittal.error_model.model' must be one of"),
        (("model", "b", "one"), "field 'planes.sagittal.error_model.b' must be a number"),
        (("model", "a_per_m", None), "field 'planes.sagittal.error_model.a_per_m' is missing"),
    ],
)
def test_balance_params_yaml_errors_name_the_field(tmp_path: Path, edit, message) -> None:
    data = BalanceParams(TEO_MASS_KG, TEO_LENGTH_M, {"sagittal": PlaneParams(PAPER_A)}).to_dict()
    section, key, value = edit
    target = data["pendulum"] if section == "pendulum" else data["planes"]["sagittal"]
    target = target if section == "pendulum" else target["error_model"]
    if value is None:
        del target[key]
    else:
        target[key] = value
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(InputFileError) as info:
        BalanceParams.from_yaml(path)
    assert message in str(info.value)
    assert str(path) in str(info.value)


def test_balance_params_rejects_other_files(tmp_path: Path) -> None:
    path = tmp_path / "other.yaml"
    path.write_text("format: something-else\nversion: 1\n")
    with pytest.raises(InputFileError, match="expected format: zmpkit-balance-params"):
        BalanceParams.from_yaml(path)
    path.write_text("pendulum: [1, 2\n")
    with pytest.raises(InputFileError, match=r"line 2: invalid YAML"):
        BalanceParams.from_yaml(path)


def test_transient_fit_survives_an_overshoot_beyond_100_percent() -> None:
    """A lean's ZMP can overshoot by more than any 2nd-order step; the fit must not crash."""
    t = np.arange(0.0, 8.0, 0.005)
    tau = np.clip(t - 1.0, 0.0, None)
    y = 0.02 * (1.0 - np.exp(-0.8 * tau) * (np.cos(6.0 * tau) - 3.0 * np.sin(6.0 * tau)))
    trial = StepTrial(time=t, zmp_measured=y, zmp_ref=0.02, t_step=1.0)
    fit = fit_transient(trial)
    assert fit.metrics is not None
    assert fit.metrics.overshoot_pct is not None
    assert fit.metrics.overshoot_pct > 100.0
    assert isinstance(fit.ok, bool)


# --- weights: trial-to-trial scatter ----------------------------------------------------------


def _scattered(seed: int, tau: float) -> tuple[np.ndarray, np.ndarray]:
    """Paper A's model at TARGETS_M with quiet trials near 0 and a relative between-trial scatter.

    Within-trial standard errors 0.01 mm at 0 to 0.06 mm at 0.10 m; between trials a scatter
    of ``tau`` × sqrt(x² + SCATTER_FLOOR_M²) (``tau`` = 0.02: ±2 % of the target).
    """
    rng = np.random.default_rng(seed)
    se = 1e-5 + 5e-5 * TARGETS_M / 0.1
    scatter = tau * np.sqrt(TARGETS_M**2 + SCATTER_FLOOR_M**2)
    y = PAPER_A.predict(TARGETS_M) + rng.normal(0.0, se) + rng.normal(0.0, scatter)
    return y, se


def test_between_trial_scatter_is_the_dersimonian_laird_closed_form() -> None:
    # equal within-trial σ: Q = RSS/σ², tr(PG) = Σ (1 - h_ii) g_i / σ², so
    # τ² = (RSS - (n - p) σ²) / Σ (1 - h_ii) g_i
    rng = np.random.default_rng(7)
    sigma = 1e-4
    y = PAPER_A.predict(TARGETS_M) + rng.normal(0.0, 1e-3, TARGETS_M.size)
    fit = fit_error_model(TARGETS_M, y, std_errors=np.full(TARGETS_M.size, sigma), model="linear")
    X = np.column_stack([TARGETS_M, np.ones_like(TARGETS_M)])
    hat = X @ np.linalg.solve(X.T @ X, X.T)
    rss = float(np.sum((y - hat @ y) ** 2))
    g = TARGETS_M**2 + SCATTER_FLOOR_M**2
    tau2 = (rss - (TARGETS_M.size - 2) * sigma**2) / float(np.sum((1.0 - np.diag(hat)) * g))
    assert fit.scatter == pytest.approx(math.sqrt(tau2), rel=1e-9)
    np.testing.assert_allclose(fit.weights, 1.0 / (sigma**2 + tau2 * g), rtol=1e-9)
    assert fit.weighting == "random_effects"


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), tau=st.floats(0.0, 0.05))
def test_weights_are_inverse_variance_without_excess_scatter_and_never_exceed_them(
    seed: int, tau: float
) -> None:
    y, se = _scattered(seed, tau)
    fit = fit_error_model(TARGETS_M, y, std_errors=se, model="quadratic")
    assert fit.scatter >= 0.0
    assert np.all(fit.weights <= 1.0 / se**2 * (1.0 + 1e-12))
    if fit.scatter == 0.0:
        np.testing.assert_allclose(fit.weights, 1.0 / se**2)
    assert fit.weight_shares.sum() == pytest.approx(1.0)


def test_scatter_takes_the_weight_off_the_quiet_trials_near_zero() -> None:
    y, se = _scattered(3, 0.03)
    inverse = fit_error_model(TARGETS_M, y, std_errors=se, weighting="inverse_variance")
    random = fit_error_model(TARGETS_M, y, std_errors=se)
    near_zero = TARGETS_M <= 0.02
    assert random.scatter > 0.0
    assert random.weight_shares[near_zero].sum() < inverse.weight_shares[near_zero].sum()
    assert inverse.scatter == 0.0


@pytest.mark.slow
def test_confidence_intervals_stay_honest_under_trial_to_trial_scatter() -> None:
    hits, n_runs = np.zeros(3), 400
    for seed in range(n_runs):
        y, se = _scattered(seed, 0.02)
        fit = fit_error_model(TARGETS_M, y, std_errors=se, model="quadratic")
        hits += [fit.interval(n)[0] < v < fit.interval(n)[1] for n, v in PAPER_A.as_dict().items()]
    # binomial standard deviation at p = 0.95, n = 400: 1.1 % (inverse-variance weights
    # ignore the scatter and cover c in about 91.5 % of the draws)
    assert np.all((hits / n_runs > 0.91) & (hits / n_runs < 0.985))


def test_unknown_weighting_is_refused() -> None:
    with pytest.raises(ParameterError, match="weighting must be one of"):
        fit_error_model(TARGETS_M, TARGETS_M, std_errors=np.ones(11), weighting="relative")
