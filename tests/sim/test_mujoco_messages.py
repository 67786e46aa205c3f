"""MuJoCo's warnings go to logging, not to the terminal and MUJOCO_LOG.TXT; the warning
counters that detect divergence still count."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from pathlib import Path

import mujoco
import numpy as np
import pytest

from zmpkit.cli.app import SIMULATING, LazyGroup, cli
from zmpkit.sim.mujoco_messages import LOGGER_NAME, route_mujoco_warnings

_BALL = '<mujoco><worldbody><body><freejoint/><geom size="0.1"/></body></worldbody></mujoco>'


@pytest.fixture
def no_handler() -> Iterator[None]:
    before = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(None)
    yield
    mujoco.set_mju_user_warning(before)


def _diverge() -> int:
    model = mujoco.MjModel.from_xml_string(_BALL)
    data = mujoco.MjData(model)
    data.qvel[0] = np.nan
    mujoco.mj_step(model, data)
    return int(data.warning[mujoco.mjtWarning.mjWARN_BADQVEL].number)


def test_a_diverging_step_is_logged_not_printed(
    no_handler: None,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capfd: pytest.CaptureFixture[str],
    caplog: pytest.LogCaptureFixture,
) -> None:
    monkeypatch.chdir(tmp_path)
    assert route_mujoco_warnings()
    with caplog.at_level(logging.DEBUG, logger=LOGGER_NAME):
        assert _diverge() == 1  # the counter that detects divergence still counts
    out, err = capfd.readouterr()
    assert "QVEL" not in out + err
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    assert any("Nan, Inf or huge value in QVEL" in r.getMessage() for r in caplog.records)
    assert route_mujoco_warnings()  # again: still ours


def test_someone_elses_handler_is_kept(no_handler: None) -> None:
    seen: list[str] = []
    mujoco.set_mju_user_warning(seen.append)
    assert not route_mujoco_warnings()
    _diverge()
    assert len(seen) == 1


def test_the_simulating_commands_install_it(no_handler: None) -> None:
    assert isinstance(cli, LazyGroup)
    assert set(cli.lazy) >= SIMULATING
    with cli.make_context("zmpkit", ["walk", "--help"], resilient_parsing=True) as ctx:
        cli.get_command(ctx, "zmp")
        assert mujoco.get_mju_user_warning() is None  # reads logs: no physics
        cli.get_command(ctx, "walk")
        assert mujoco.get_mju_user_warning() is not None
