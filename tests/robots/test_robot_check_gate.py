"""Every command that runs a user's robot refuses one that fails ``zmpkit robot check``.

The biped's robot.yaml is written from its model; then a tail (a capsule from the pelvis to
the floor, which no F-T sensor carries) is added to the model: the F-T ZMP no longer
agrees with MuJoCo's contact ZMP, and ``balance``, ``sim push`` and ``walk`` stop before any
work with one line naming the gap.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from helpers.biped import BIPED_MJCF, write_biped_robot
from zmpkit.cli import main

PELVIS_GEOM = '<geom type="box" size="0.06 0.1 0.04" mass="2"/>'
TAIL = '<geom type="capsule" fromto="-0.2 0 0 -0.2 0 -0.56" size="0.02" mass="0.05"/>'


@pytest.fixture(scope="module")
def tailed_robot_yaml(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("tailed")
    robot_yaml = write_biped_robot(folder)
    model = folder / "biped.xml"
    model.write_text(BIPED_MJCF.replace(PELVIS_GEOM, PELVIS_GEOM + TAIL, 1), encoding="utf-8")
    return robot_yaml


@pytest.mark.parametrize(
    "command",
    [
        ["balance", "--quick"],
        ["sim", "push", "--targets", "0,0.01"],
        ["walk", "--duration", "3"],
    ],
)
def test_a_robot_failing_its_check_is_refused_in_one_line(
    tailed_robot_yaml: Path, command: list[str], tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    out = tmp_path / "never"
    assert main([*command, "--robot", str(tailed_robot_yaml), "--out", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "fails its robot check: the F-T ZMP lies" in line
    assert f"zmpkit robot check {tailed_robot_yaml}" in line
    assert not out.exists()


def test_robot_check_itself_still_reports_the_failing_robot(
    tailed_robot_yaml: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["robot", "check", str(tailed_robot_yaml)]) == 1
    assert "MISMATCH" in capsys.readouterr().out
