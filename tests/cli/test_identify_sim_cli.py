"""identify sim's options reach the fit's configuration."""

from __future__ import annotations

from pathlib import Path

import pytest

from zmpkit.cli import identify
from zmpkit.cli.app import main
from zmpkit.simfit.noise_intervals import NoiseInterval
from zmpkit.simfit.refit_intervals import REFIT_REPLICAS, RefitInterval


class _StopError(Exception):
    """Raised by the stand-in fit once it has the configuration."""


@pytest.fixture
def seen(monkeypatch: pytest.MonkeyPatch) -> list:
    configs: list = []

    def fit(config, out_dir, progress=None, replica_progress=None):
        configs.append(config)
        raise _StopError

    monkeypatch.setattr(identify, "run_identify_sim", fit)
    return configs


def _fit_config(tmp_path: Path, seen: list, *options: str):
    with pytest.raises(_StopError):
        main(["identify", "sim", "--self-test", *options, "--out", str(tmp_path / "o")])
    return seen[-1]


def test_popsize_reaches_the_fit(tmp_path: Path, seen: list) -> None:
    assert _fit_config(tmp_path, seen, "--popsize", "64").popsize == 64
    default = _fit_config(tmp_path, seen)
    assert default.popsize is None  # sized to the backend (simfit.population)
    assert default.restarts is None  # as many as the wall-time budget allows


def test_restarts_reach_the_fit(tmp_path: Path, seen: list) -> None:
    assert _fit_config(tmp_path, seen, "--restarts", "3").restarts == 3


def test_window_reaches_the_fit(tmp_path: Path, seen: list) -> None:
    assert _fit_config(tmp_path, seen, "--window", "0.9").window_s == 0.9
    assert _fit_config(tmp_path, seen).window_s == 1.2


def test_burn_in_reaches_the_fit(tmp_path: Path, seen: list) -> None:
    config = _fit_config(tmp_path, seen, "--window", "2", "--burn-in", "1")
    assert (config.window_s, config.burn_in_s) == (2.0, 1.0)
    assert _fit_config(tmp_path, seen).burn_in_s == 0.3


def test_interval_replicas_reach_the_fit(tmp_path: Path, seen: list) -> None:
    assert _fit_config(tmp_path, seen, "--interval-replicas", "0").interval_replicas == 0
    assert _fit_config(tmp_path, seen).interval_replicas == REFIT_REPLICAS


def test_one_interval_replica_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["identify", "sim", "--self-test", "--interval-replicas", "1", "--out", str(tmp_path)]
    assert main(argv) == 2
    assert "interval_replicas must be 0" in capsys.readouterr().err


def test_a_window_not_longer_than_its_burn_in_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["identify", "sim", "--self-test", "--window", "0.3", "--out", str(tmp_path)]) == 2
    assert "--window" in capsys.readouterr().err
    argv = ["identify", "sim", "--self-test", "--window", "1", "--burn-in", "1.5"]
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    error = capsys.readouterr().err
    assert "--burn-in 1.5 s" in error
    assert "Traceback" not in error
    assert not (tmp_path / "o").exists()


def test_the_interval_line_says_its_centre_and_bias_when_corrected() -> None:
    refit = RefitInterval("gear", 800.0, 800.0, (0.02, 0.04, 0.03))
    text = identify._interval_text(refit)
    assert f"[{refit.lower:.6g}, {refit.upper:.6g}]" in text
    assert "about the bias-corrected 776" in text
    assert "estimator bias +3 %" in text
    assert identify._interval_text(NoiseInterval("pid", 0.6, 0.02, 4)) == (
        "95 % interval [0.588, 0.612] (±2 %)"
    )
