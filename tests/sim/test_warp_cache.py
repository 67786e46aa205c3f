"""The persistent kernel cache of MuJoCo Warp: its location rule and the warm-up command.

The location rule and the command's answers without MuJoCo Warp run everywhere; the
warm-up itself (``needs_warp``, slow: a fresh cache compiles every kernel of a robot's
step, minutes on Warp's CPU device) runs in a subprocess, as Warp's cache folder is fixed
once per process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from zmpkit.cli.app import main
from zmpkit.sim.warp_cache import (
    CACHE_ENV,
    cache_file_count,
    configure_kernel_cache,
    warp_cache_base,
)


@pytest.mark.parametrize(
    ("environ", "expected"),
    [
        ({CACHE_ENV: "/data/zk", "XDG_CACHE_HOME": "/xdg"}, "/data/zk/warp"),
        ({CACHE_ENV: "", "XDG_CACHE_HOME": "/xdg"}, "/xdg/zmpkit/warp"),
        ({"XDG_CACHE_HOME": "/xdg"}, "/xdg/zmpkit/warp"),
        ({"XDG_CACHE_HOME": "relative/xdg"}, "HOME/.cache/zmpkit/warp"),  # XDG: ignored
        ({"XDG_CACHE_HOME": ""}, "HOME/.cache/zmpkit/warp"),
        ({}, "HOME/.cache/zmpkit/warp"),
    ],
)
def test_location_rule(environ, expected, monkeypatch, tmp_path) -> None:
    monkeypatch.setenv("HOME", str(tmp_path))
    want = Path(expected.replace("HOME", str(tmp_path)))
    assert warp_cache_base(environ) == want


def test_home_in_zmpkit_cache_dir_is_expanded(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv("HOME", str(tmp_path))
    assert warp_cache_base({CACHE_ENV: "~/zk"}) == tmp_path / "zk" / "warp"


def fake_warp(kernel_cache_dir: str | None = None) -> SimpleNamespace:
    """A stand-in for the ``warp`` module: only its ``config.kernel_cache_dir``."""
    return SimpleNamespace(config=SimpleNamespace(kernel_cache_dir=kernel_cache_dir))


def test_configure_sets_warps_cache_before_init() -> None:
    wp = fake_warp()
    assert configure_kernel_cache(wp, {CACHE_ENV: "/data/zk"})
    assert wp.config.kernel_cache_dir == "/data/zk/warp"


@pytest.mark.parametrize(
    ("wp", "environ"),
    [
        (fake_warp(), {"WARP_CACHE_PATH": "/warp-own", CACHE_ENV: "/data/zk"}),
        (fake_warp("/chosen/or/initialised"), {CACHE_ENV: "/data/zk"}),
    ],
)
def test_warps_own_setting_wins(wp, environ) -> None:
    before = wp.config.kernel_cache_dir
    assert not configure_kernel_cache(wp, environ)
    assert wp.config.kernel_cache_dir == before


def test_cache_file_count(tmp_path) -> None:
    assert cache_file_count(tmp_path / "absent") == 0
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "k.o").write_bytes(b"")
    (tmp_path / "m.cpp").write_text("")
    assert cache_file_count(tmp_path) == 2


def test_cache_command_prints_the_location(monkeypatch, tmp_path, capsys) -> None:
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    assert main(["warp", "cache"]) == 0
    assert capsys.readouterr().out.startswith(f"{tmp_path / 'warp'}/<warp version>")


def test_warm_up_without_warp_exits_2_naming_the_extra(monkeypatch, capsys) -> None:
    monkeypatch.setitem(sys.modules, "mujoco_warp", None)  # makes `import mujoco_warp` fail
    assert main(["warp", "warm-up", "--robot", "nao", "--device", "cpu"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "pip install 'zmpkit[gpu]'" in err


WARM_UP = """
import json, sys
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.warp_warm_up import warm_up_warp
r = warm_up_warp([get_robot("nao")], "M,G,S", "cpu")
print(json.dumps({"dir": r.cache_dir, "before": r.files_before, "after": r.files_after,
                  "skipped": [w.skipped for w in r.robots]}))
"""


@pytest.mark.needs_warp
@pytest.mark.slow
def test_warm_up_fills_the_cache_once(tmp_path) -> None:
    """A first warm-up compiles into zmpkit's folder; a second compiles nothing new."""
    env = os.environ | {CACHE_ENV: str(tmp_path)}
    env.pop("WARP_CACHE_PATH", None)
    runs = []
    for _ in range(2):
        out = subprocess.run(
            [sys.executable, "-c", WARM_UP], env=env, capture_output=True, text=True, check=True
        )
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    first, second = runs
    assert Path(first["dir"]).parent == tmp_path / "warp"  # Warp adds its version folder
    assert first["skipped"] == [None]
    assert first["before"] == 0 < first["after"]
    assert second["dir"] == first["dir"]
    assert second["before"] == second["after"] == first["after"]
