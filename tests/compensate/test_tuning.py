"""Tuning improves its objective on a seeded short walk; evaluations are cached and resumed;
the pipeline's summary.json keeps its contract."""

from __future__ import annotations

import json

import numpy as np
import pytest

from zmpkit.compensate.algorithm1 import compensate_abstraction
from zmpkit.compensate.evaluations import WalkSpec, evaluate_all
from zmpkit.compensate.methods import CompensatedWalk
from zmpkit.compensate.offsets import OffsetParameters
from zmpkit.compensate.summary import EXTRA_SUMMARY_KEYS, SUMMARY_KEYS, summary_of
from zmpkit.compensate.tuning import TuningResult, objective, prior_from_offset, tune_offset
from zmpkit.errors import ParameterError
from zmpkit.pipelines.walk_compensate import CompensateConfig, CompensateResult, run_walk_compensate
from zmpkit.pipelines.walk_compensate_files import write_walk_compensate
from zmpkit.robots.nao import nao_ik_model
from zmpkit.robots.registry import get_robot
from zmpkit.walking import generate_pattern

SHORT = WalkSpec(speed_mps=0.2, seed=0, duration_s=3.0, robot=get_robot("nao"))


@pytest.mark.slow
def test_tuning_improves_on_no_offset_and_resumes_from_its_cache(tmp_path) -> None:
    config = SHORT.walk_config().pattern_config()
    model_offset = compensate_abstraction(
        config, nao_ik_model(), iterations=3, ik_settings=get_robot("nao").ik_settings
    )
    prior = prior_from_offset("half-sine", model_offset.zmp_offset_in_world,
                              generate_pattern(config))  # fmt: skip
    result = tune_offset(prior, [SHORT], evaluations=2, cache_dir=tmp_path, workers=1, seed=3)
    assert len(result.history) == 3
    assert result.best_objective < 2.0  # J = 2 is the walk without offset
    assert result.best_objective == min(j for _, j in result.history)
    files = sorted(tmp_path.glob("*.json"))
    assert len(files) == 4  # baseline, prior, two candidates
    again = evaluate_all([(SHORT, result.best)], tmp_path, workers=1)[0]
    assert objective([again], result.baseline) == pytest.approx(result.best_objective)
    assert len(sorted(tmp_path.glob("*.json"))) == 4


def _walk(peak: float, std: float, rms=()) -> CompensatedWalk:
    t = np.arange(400) * 0.01
    pitch = std * np.sqrt(2) * np.sin(2 * np.pi * 2 * t)
    zmp = np.zeros((t.size, 2))
    return CompensatedWalk(SHORT, peak, std, False, t, pitch, (0.5, 3.5), zmp, zmp, zmp, rms)


@pytest.mark.parametrize("method", ["alg1", "half-sine"])
def test_summary_json_has_exactly_the_contract_keys(tmp_path, method) -> None:
    config = CompensateConfig(method=method)
    rms = (0.01, 0.001) if method == "alg1" else ()
    label = "alg1" if method == "alg1" else "half-sine"
    baseline, compensated = (_walk(0.04, 0.03),), (_walk(0.02, 0.015, rms),)
    summary = summary_of(method, baseline, compensated)
    tuned = OffsetParameters("half-sine", 0.004, 0.25, (0.001, -0.002), 0.2)
    tuning = {"half-sine": TuningResult("half-sine", tuned, tuned, 1.4, ((tuned, 1.4),), ())}
    result = CompensateResult(config, summary, label, baseline, {label: compensated}, tuning)
    files = write_walk_compensate(result, tmp_path).files
    written = json.loads(files["summary"].read_text())
    expected = set(SUMMARY_KEYS) | set(EXTRA_SUMMARY_KEYS)
    expected |= {"iteration_rms_m"} if method == "alg1" else set()
    assert set(written) == expected
    assert written["peak_reduction_pct"] == pytest.approx(50.0)
    assert written["std_reduction_pct"] == pytest.approx(50.0)
    report = files["report"].read_text()
    assert files["report"].name == "report.html"
    assert "lowers the step-frequency peak of the trunk pitch" in report
    assert "50.0 % lower on average over 1 held-out walks" in report
    assert (
        "half-sine: tuned objective J = 1.400 (2 = no change), offset amplitude_m = 0.004, "
        "phase = 0.25, fourier_m = [0.001, -0.002], reference_speed_mps = 0.2"
    ) in report
    for role in ("spectrum", "boxes", "zmp_target"):
        assert files[role].stat().st_size > 0


def test_bad_method_is_named() -> None:
    with pytest.raises(ParameterError, match="method must be one of alg1, alg2, half-sine"):
        CompensateConfig(method="magic")


@pytest.mark.slow
def test_quick_alg1_run_writes_its_summary(tmp_path) -> None:
    result = run_walk_compensate(CompensateConfig(method="alg1", quick=True), tmp_path)
    write_walk_compensate(result, tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert len(summary["iteration_rms_m"]) == 10
    assert summary["iteration_rms_m"][-1] < 0.1 * summary["iteration_rms_m"][0]
    assert len(summary["validation_walks"]) == len(result.config.validation_walks())


@pytest.mark.slow
def test_walk_compensate_command_writes_the_summary_contract(tmp_path) -> None:
    import json

    from zmpkit.cli import main

    out = tmp_path / "comp"
    assert main(["walk", "compensate", "--method", "half-sine", "--quick", "--out", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    for key in (
        "method",
        "baseline_peak_amplitude_rad",
        "compensated_peak_amplitude_rad",
        "peak_reduction_pct",
        "baseline_std_rad",
        "compensated_std_rad",
        "std_reduction_pct",
        "validation_walks",
    ):
        assert key in summary
    assert summary["method"] == "half-sine"
    assert summary["walks_compared"] >= 1
