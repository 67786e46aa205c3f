"""balance's options reach the run's configuration."""

from __future__ import annotations

from pathlib import Path

import pytest

from zmpkit.cli import balance
from zmpkit.cli.app import main
from zmpkit.control import PAPER_A_TIME_SCALE
from zmpkit.pipelines.balance import FAST_TIME_SCALE, FAST_ZETA


class _StopError(Exception):
    """Raised by the stand-in run once it has the configuration."""


@pytest.fixture
def seen(monkeypatch: pytest.MonkeyPatch) -> list:
    configs: list = []

    def run(config, out_dir, progress=None, echo=None):
        configs.append(config)
        raise _StopError

    monkeypatch.setattr(balance, "run_balance", run)
    return configs


@pytest.mark.parametrize(
    ("pace", "time_scale", "paced", "zeta"),
    [
        ("servo", 1.0, True, 0.8),
        ("fast", FAST_TIME_SCALE, False, FAST_ZETA),
        ("paper", PAPER_A_TIME_SCALE, False, 0.8),
    ],
)
def test_dlipm_pace_sets_the_time_scale_and_damping(
    tmp_path: Path, seen: list, pace: str, time_scale: float, paced: bool, zeta: float
) -> None:
    with pytest.raises(_StopError):
        main(["balance", "--quick", "--dlipm-pace", pace, "--out", str(tmp_path / "o")])
    config = seen[0]
    assert (config.time_scale, config.servo_paced, config.zeta) == (time_scale, paced, zeta)


def test_feedback_and_faults_reach_the_run(tmp_path: Path, seen: list) -> None:
    argv = ["balance", "--quick", "--dlipm-feedback", "--fault", "nan", "--fault", "spike"]
    with pytest.raises(_StopError):
        main([*argv, "--fault", "nan", "--out", str(tmp_path / "o")])
    assert seen[0].dlipm_feedback
    assert seen[0].faults == ("nan", "spike")  # each kind once, in the order given
