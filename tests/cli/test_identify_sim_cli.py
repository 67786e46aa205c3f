"""identify sim's options reach the fit's configuration."""

from __future__ import annotations

from pathlib import Path

import pytest

from zmpkit.cli import identify
from zmpkit.cli.app import main


class _StopError(Exception):
    """Raised by the stand-in fit once it has the configuration."""


def test_popsize_reaches_the_fit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    seen = []

    def fit(config, out_dir, progress=None):
        seen.append(config)
        raise _StopError

    monkeypatch.setattr(identify, "run_identify_sim", fit)
    argv = ["identify", "sim", "--self-test", "--popsize", "64", "--out", str(tmp_path / "o")]
    with pytest.raises(_StopError):
        main(argv)
    assert seen[0].popsize == 64
    seen.clear()
    with pytest.raises(_StopError):
        main(["identify", "sim", "--self-test", "--out", str(tmp_path / "p")])
    assert seen[0].popsize is None  # CMA-ES's own default
    assert seen[0].restarts == 0  # one run


def test_restarts_reach_the_fit(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    seen = []

    def fit(config, out_dir, progress=None):
        seen.append(config)
        raise _StopError

    monkeypatch.setattr(identify, "run_identify_sim", fit)
    argv = ["identify", "sim", "--self-test", "--restarts", "3", "--out", str(tmp_path / "o")]
    with pytest.raises(_StopError):
        main(argv)
    assert seen[0].restarts == 3
