"""Whole-body IK of a walking pattern reaches its targets."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from zmpkit.errors import ModelError
from zmpkit.robots.nao import nao_ik_model
from zmpkit.robots.registry import get_robot
from zmpkit.sim.names import sole_site
from zmpkit.walking import PatternConfig, generate_pattern
from zmpkit.walking.ik import IkSettings, solve_walking_ik

TOLERANCE_M = 1e-4
"""Stated IK accuracy for NAO's walk: CoM and sole centres within 0.1 mm."""


@pytest.fixture(scope="module")
def solved():
    pattern = generate_pattern(PatternConfig(n_steps=4, duration_s=None, com_height_m=0.25))
    model = nao_ik_model()
    return pattern, model, solve_walking_ik(pattern, model, get_robot("nao").ik_settings)


def test_ik_reaches_com_and_feet(solved) -> None:
    _, _, trajectory = solved
    assert trajectory.max_com_error_m < TOLERANCE_M
    assert trajectory.max_foot_error_m < TOLERANCE_M
    assert trajectory.max_torso_error_rad < 1e-3


def test_forward_kinematics_of_the_solution_puts_soles_on_the_plan(solved) -> None:
    pattern, model, trajectory = solved
    data = mujoco.MjData(model)
    for k in range(0, pattern.time_s.size, 37):
        data.qpos[:7] = trajectory.base_qpos[k]
        for name, angle in zip(trajectory.joint_names, trajectory.q_rad[k], strict=True):
            data.qpos[model.joint(name).qposadr[0]] = angle
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        for side, foot in (("left", pattern.feet.left), ("right", pattern.feet.right)):
            site = data.site(sole_site(side)).xpos
            assert site == pytest.approx(foot.position_in_world[k], abs=TOLERANCE_M)
        assert data.subtree_com[1] == pytest.approx(pattern.com_position_in_world[k], abs=1e-4)


def test_coupled_hip_yaw_pitch_stays_equal(solved) -> None:
    _, _, trajectory = solved
    assert np.allclose(
        trajectory.joint("LHipYawPitch"), trajectory.joint("RHipYawPitch"), atol=1e-6
    )


def test_unknown_joint_is_named() -> None:
    pattern = generate_pattern(PatternConfig(n_steps=2, duration_s=None))
    with pytest.raises(ModelError, match="no joint 'Elbow'"):
        solve_walking_ik(pattern, nao_ik_model(), IkSettings(joint_names=("Elbow",)))
