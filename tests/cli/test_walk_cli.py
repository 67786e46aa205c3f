"""``zmpkit walk``: the controller, command and push options, end to end and on bad input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from zmpkit.cli import main


@pytest.mark.slow
def test_a_pushed_closed_loop_walk_writes_its_controller_and_outcome(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "walk"
    code = main(["walk", "--effects", "none", "--duration", "2", "--controller", "zmpip",
                 "--lateral-speed", "0.01", "--push", "5@1.5:-y", "--out", str(out)])  # fmt: skip
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["controller"] == "zmpip"
    assert summary["pushes"] == ["5@1.5:-y"]
    assert summary["commanded_lateral_speed_mps"] == 0.01
    assert summary["fell"] is False
    assert summary["fall_kind"] is None
    assert "zmpip: fell: False" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--push", "20@3:up"], "a push is FORCE_N@TIME_S"),
        (["--controller", "mpc"], "Invalid value for '--controller'"),
    ],
)
def test_bad_walk_options_are_exit_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    code = main(["walk", *args, "--out", str(tmp_path / "w")])
    assert code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "w").exists()


class _StoppedError(Exception):
    """Raised instead of running the compensation: the config it got."""


@pytest.mark.parametrize(
    ("args", "controller"),
    [
        (["--method", "alg1"], "open"),  # paper B ran Algorithm 1 open loop (Fig. 5)
        (["--method", "alg1", "--controller", "zmpip"], "zmpip"),  # asked for: kept
        (["--method", "alg2"], "zmpip"),
        ([], "zmpip"),
    ],
)
def test_walk_compensate_runs_algorithm_1_open_loop_by_default(
    args: list[str], controller: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def stop(config: object, *_: object, **__: object) -> None:
        raise _StoppedError(config)

    monkeypatch.setattr("zmpkit.cli.walk.run_walk_compensate", stop)
    with pytest.raises(_StoppedError) as stopped:
        main(["walk", "compensate", *args, "--out", str(tmp_path / "c")])
    assert stopped.value.args[0].controller == controller
