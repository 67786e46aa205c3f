"""The ``zmpkit`` command: help, version, the ``zmp`` subcommand end to end, and bad input."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import click
import numpy as np
import pytest

from helpers.ft_data import wrench_in_sensor, write_log
from zmpkit import __version__
from zmpkit.cli import main
from zmpkit.cli.app import COMMANDS, cli
from zmpkit.io import read_feet_yaml

pytestmark = pytest.mark.filterwarnings("error")


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert __version__ in capsys.readouterr().out


@pytest.mark.parametrize("sub", [[], ["zmp"], ["demo"]])
def test_help_on_every_subcommand(sub: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*sub, "--help"]) == 0
    assert "Usage: zmpkit" in capsys.readouterr().out


def _log_of_known_loads(path: Path, feet_yaml: Path) -> tuple[Path, np.ndarray]:
    """Three samples: double support, right only, airborne. Returns the expected ZMPs."""
    feet = read_feet_yaml(feet_yaml)
    right_point, left_point = np.array([0.05, -0.13, 0.0]), np.array([-0.02, 0.12, 0.0])
    rows, expected = [], []
    for k, (fz_r, fz_l) in enumerate([(300.0, 100.0), (600.0, 2.0), (0.0, 0.0)]):
        w_r = wrench_in_sensor(
            right_point, np.array([0, 0, fz_r]), feet["right"].position, feet["right"].rotation
        )
        w_l = wrench_in_sensor(
            left_point, np.array([0, 0, fz_l]), feet["left"].position, feet["left"].rotation
        )
        rows.append([k * 0.01, *w_r, *w_l])
    expected = [(0.75 * right_point + 0.25 * left_point)[:2], right_point[:2], None]
    return write_log(path, rows), expected


def test_zmp_end_to_end(tmp_path: Path, feet_yaml: Path) -> None:
    log, expected = _log_of_known_loads(tmp_path / "log.csv", feet_yaml)
    out = tmp_path / "out"
    assert main(["zmp", str(log), "--feet", str(feet_yaml), "--out", str(out)]) == 0
    with (out / "zmp.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["time", "zmp_x", "zmp_y", "contact_right", "contact_left"]
    for row, want in zip(rows[:2], expected[:2], strict=True):
        assert float(row["zmp_x"]) == pytest.approx(want[0], abs=1e-12)
        assert float(row["zmp_y"]) == pytest.approx(want[1], abs=1e-12)
    assert (rows[1]["contact_right"], rows[1]["contact_left"]) == ("1", "0")
    assert (rows[2]["zmp_x"], rows[2]["zmp_y"], rows[2]["contact_right"]) == ("", "", "0")
    assert (out / "zmp.png").stat().st_size > 1000


def test_zmp_bad_csv_exits_2_with_one_line(
    tmp_path: Path, feet_yaml: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    log = tmp_path / "log.csv"
    log.write_text("time,right_fx\n0.0,1.0\n")
    code = main(["zmp", str(log), "--feet", str(feet_yaml), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert err.startswith("zmpkit: error: ")
    assert "missing column 'right_fy'" in err


def test_zmp_needs_exactly_one_feet_source(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["zmp", "log.csv", "--out", str(tmp_path)]) == 2
    assert "give exactly one of --feet FEET.yaml or --robot ROBOT" in capsys.readouterr().err


def test_unknown_robot_lists_choices(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["zmp", "log.csv", "--robot", "atlas", "--out", str(tmp_path)]) == 2
    assert "robot must be one of nao, op3, teo; got 'atlas'" in capsys.readouterr().err


def test_zmp_with_builtin_teo_mounts(tmp_path: Path) -> None:
    from zmpkit.io import feet_from_mapping
    from zmpkit.robots.teo import teo_feet_mounts

    feet = feet_from_mapping(teo_feet_mounts())
    point_x, weight_n = 0.03, 307.0
    row = [0.0]
    for name in ("right", "left"):
        m = feet[name]
        point = np.array([point_x, m.position[1], m.ground_height])
        row += list(wrench_in_sensor(point, np.array([0, 0, weight_n]), m.position, m.rotation))
    log = write_log(tmp_path / "log.csv", [row])
    assert main(["zmp", str(log), "--robot", "teo", "--out", str(tmp_path / "o")]) == 0
    with (tmp_path / "o" / "zmp.csv").open() as f:
        (out_row,) = list(csv.DictReader(f))
    assert float(out_row["zmp_x"]) == pytest.approx(point_x, abs=1e-12)
    assert float(out_row["zmp_y"]) == pytest.approx(0.0, abs=1e-12)


def test_the_root_help_lists_each_command_with_its_own_help() -> None:
    """The lazy group's one-line helps are the commands' own (no drift)."""
    ctx = click.Context(cli)
    for name, (_, short_help) in COMMANDS.items():
        command = cli.get_command(ctx, name)
        assert command is not None
        assert command.get_short_help_str(limit=300) == short_help


def test_the_root_help_imports_no_physics() -> None:
    """``zmpkit --help`` answers without importing the pipelines or MuJoCo (lazy subcommands)."""
    code = (
        "import sys; from zmpkit.cli import main; main(['--help']); "
        "print(sorted(m for m in ('mujoco', 'zmpkit.pipelines', 'scipy') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().splitlines()[-1] == "[]"
