"""A walk the robot's legs cannot follow is refused before it is simulated, not a fall.

The test biped asked to walk with its CoM at 0.62 m, above what its legs reach: the
whole-body IK leaves the CoM and the soles centimetres from the plan (the built-in robots'
walks leave at most 0.14 mm), and ``zmpkit walk`` says so in one line, exit 2.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest

from helpers.biped import write_biped_robot
from zmpkit.cli import main
from zmpkit.errors import ParameterError
from zmpkit.experiments.walk import IK_REALISABLE_M, check_realisable
from zmpkit.walking.ik import JointTrajectory


@pytest.mark.slow
def test_a_walk_above_the_legs_reach_is_refused_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    robot_yaml = write_biped_robot(tmp_path)
    with robot_yaml.open("a", encoding="utf-8") as f:
        f.write("walking:\n  com_height: 0.62\n")
    out = tmp_path / "walk"
    capsys.readouterr()
    assert main(["walk", "--robot", str(robot_yaml), "--duration", "3", "--out", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert (
        "the robot's legs cannot follow this walk's plan: the whole-body IK leaves the CoM" in line
    )
    assert f"more than {1e3 * IK_REALISABLE_M:g} mm" in line
    assert not out.exists()


def _trajectory(com_error: float, foot_error: float) -> JointTrajectory:
    n = 5
    return JointTrajectory(
        time_s=np.linspace(0.0, 0.4, n),
        joint_names=("j",),
        q_rad=np.zeros((n, 1)),
        base_qpos=np.zeros((n, 7)),
        com_error_m=np.array([0.0, com_error, 0.0, 0.0, 0.0]),
        foot_error_m=np.array([0.0, 0.0, 0.0, foot_error, 0.0]),
        torso_error_rad=np.zeros(n),
    )


def test_the_bar_is_the_ik_error_and_names_when() -> None:
    check_realisable(_trajectory(IK_REALISABLE_M, IK_REALISABLE_M))  # on the bar: realisable
    with pytest.raises(ParameterError, match=r"CoM 6\.0 mm off \(at 0\.10 s\) and a sole 1\.0"):
        check_realisable(_trajectory(0.006, 0.001))
    with pytest.raises(ParameterError, match=r"a sole 20\.0 mm off \(at 0\.30 s\)"):
        check_realisable(_trajectory(0.0, 0.02))


def test_the_refusal_names_the_joints_held_at_their_limits() -> None:
    """The Berkeley Humanoid's walk was refused with only its IK errors; its ankle pitch
    (range −0.524 to 0.698 rad) sat at its limit when the plan was missed most."""
    model = mujoco.MjModel.from_xml_string(
        '<mujoco><compiler angle="radian"/><worldbody><body>'
        '<joint name="ankle" range="-0.524 0.698"/>'
        '<joint name="knee" range="0 2"/><geom size="0.1"/></body></worldbody></mujoco>'
    )
    trajectory = _trajectory(0.0, 0.02)
    q = np.zeros((5, 2))
    q[3] = (-0.524, 0.5)  # the row of the largest error: the ankle at its lower limit
    trajectory = replace(trajectory, joint_names=("ankle", "knee"), q_rad=q)
    match = r"at 0\.30 s ankle at its lower limit \(-0\.524 rad\); try"
    with pytest.raises(ParameterError, match=match):
        check_realisable(trajectory, model)
    q[3] = (0.0, 0.5)  # nothing at a limit: nothing named
    with pytest.raises(ParameterError, match=r"more than 5 mm; try"):
        check_realisable(replace(trajectory, q_rad=q), model)
