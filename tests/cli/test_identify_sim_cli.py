"""identify sim's options reach the fit's configuration."""

from __future__ import annotations

from pathlib import Path

import pytest

from zmpkit.cli import identify
from zmpkit.cli.app import main


class _StopError(Exception):
    """Raised by the stand-in fit once it has the configuration."""


@pytest.fixture
def seen(monkeypatch: pytest.MonkeyPatch) -> list:
    configs: list = []

    def fit(config, out_dir, progress=None):
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
    assert default.popsize is None  # CMA-ES's own default
    assert default.restarts == 0  # one run


def test_restarts_reach_the_fit(tmp_path: Path, seen: list) -> None:
    assert _fit_config(tmp_path, seen, "--restarts", "3").restarts == 3
