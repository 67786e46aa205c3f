"""A robot leans only in the planes its ankles can lean it in.

The test biped without its ankle roll joints keeps its hip roll: before, the frontal lean
used the hip roll as its pivot (a lean the robot cannot make; the fit then failed on a
negative slope). Now its balance model has the sagittal plane only, says why not the
frontal, and a command asking for the frontal plane stops in one line.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from helpers.biped import BIPED_MJCF, write_biped_robot
from zmpkit.cli import main
from zmpkit.robots.registry import get_robot


@pytest.fixture(scope="module")
def no_ankle_roll(tmp_path_factory: pytest.TempPathFactory) -> Path:
    text = re.sub(r'\s*<joint name="[rl]_ankle_roll"[^>]*/>', "", BIPED_MJCF)
    assert "ankle_roll" not in text
    return write_biped_robot(tmp_path_factory.mktemp("no_ankle_roll"), text)


def test_the_balance_model_has_the_planes_its_ankles_lean_in(no_ankle_roll: Path) -> None:
    balance = get_robot(str(no_ankle_roll)).require_balance()
    assert balance.planes == ("sagittal",)
    assert balance.lean_joints == {"sagittal": ("r_ankle_pitch", "l_ankle_pitch")}
    assert balance.missing_planes == {"frontal": "neither leg has an ankle roll joint"}
    full = get_robot("teo").require_balance()
    assert full.planes == ("sagittal", "frontal")
    assert full.missing_planes == {}


@pytest.mark.parametrize(
    "command",
    [
        ["balance", "--quick", "--plane", "frontal"],
        ["sim", "push", "--plane", "frontal", "--targets", "0,0.005"],
    ],
)
def test_a_plane_the_robot_cannot_lean_in_is_one_line(
    no_ankle_roll: Path, command: list[str], tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    out = tmp_path / "never"
    assert main([*command, "--robot", str(no_ankle_roll), "--out", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.endswith(
        "the robot cannot lean in the frontal plane: neither leg has an ankle roll joint; "
        "it can lean in: sagittal"
    )
    assert not out.exists()


def test_a_report_says_which_effects_a_robot_without_truth_simulated(
    no_ankle_roll: Path,
) -> None:
    """A robot file without a truth has no motor, gear or link values: ``all`` runs its
    sensor errors only, and the reports say so instead of "every effect on"."""
    robot = get_robot(str(no_ankle_roll))
    assert robot.simulated_effects_note("all") == (
        " (simulated: S; the robot has no truth values for M, I, G, F)"
    )
    assert robot.simulated_effects_note("S") == ""
    assert robot.simulated_effects_note("none") == ""
    assert get_robot("nao").simulated_effects_note("all") == ""  # a truth for every effect
