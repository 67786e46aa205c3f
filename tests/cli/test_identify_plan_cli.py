"""identify plan: bad input gets one line and exit 2; the options reach the plan."""

from __future__ import annotations

from pathlib import Path

import pytest

from zmpkit.cli import identify_plan
from zmpkit.cli.app import main


def _one_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "Traceback" not in err
    return err


def test_a_walk_too_short_is_refused_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["identify", "plan", "--duration", "0.2", "--out", str(tmp_path / "o")])
    assert code == 2
    assert "0.2" in _one_line(capsys)
    assert not (tmp_path / "o").exists()


def test_unknown_effects_are_refused_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["identify", "plan", "--effects", "M,Q", "--out", str(tmp_path / "o")])
    assert code == 2
    assert "Q" in _one_line(capsys)


def test_a_robot_without_a_fit_catalogue_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["identify", "plan", "--robot", "nosuchrobot", "--out", str(tmp_path / "o")])
    assert code == 2
    assert "nosuchrobot" in _one_line(capsys)


def test_the_options_reach_the_plan(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    seen = []

    class _StopError(Exception):
        """Raised by the stand-in plan once it has the configuration."""

    def plan(config, out_dir, progress=None):
        seen.append(config)
        raise _StopError

    monkeypatch.setattr(identify_plan, "run_identify_plan", plan)
    with pytest.raises(_StopError):
        main(["identify", "plan", "--effects", "M,G,S", "--quick", "--duration", "4",
              "--workers", "1", "--seed", "3", "--out", str(tmp_path / "o")])  # fmt: skip
    config = seen[-1]
    assert (config.effects, config.quick, config.duration_s) == ("M,G,S", True, 4.0)
    assert (config.workers, config.seed, config.robot.name) == (1, 3, "nao")
