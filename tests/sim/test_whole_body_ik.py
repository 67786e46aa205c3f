"""The one whole-body IK (mink): soles held, CoM moved, its stop rule and its boundary checks."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from helpers.biped import write_biped_robot
from zmpkit.errors import ModelError, ParameterError
from zmpkit.robots.nao import nao_ik_model
from zmpkit.robots.registry import get_robot
from zmpkit.robots.robot_file_reader import draft_robot_file
from zmpkit.robots.user_model import user_model
from zmpkit.robots.user_walking import crouch
from zmpkit.sim.names import sole_site
from zmpkit.sim.whole_body_ik import IkCosts, IkStop, WholeBodyIk, yaw_pose

SIDES = ("left", "right")
DEPTH_M = 0.01
"""How far the tests lower the CoM [m]."""
SOLE_HOLD_M = 1e-4
"""How still a held sole stays while the CoM moves [m] (the walk's stated IK accuracy)."""


def _nao_ik(costs: IkCosts, torso: str | None = None) -> WholeBodyIk:
    """NAO's IK model at its walking crouch (the walk's start posture)."""
    model = nao_ik_model()
    q = model.qpos0.copy()
    for name, angle in get_robot("nao").ik_settings.posture_rad.items():
        q[model.joint(name).qposadr[0]] = angle
    soles = {side: sole_site(side) for side in SIDES}
    return WholeBodyIk(model, q, soles, costs, torso_body=torso)


def _soles(ik: WholeBodyIk) -> np.ndarray:
    data = ik.configuration.data
    return np.array([data.site(sole_site(side)).xpos for side in SIDES])


def test_held_soles_stay_while_the_com_goes_down_by_the_asked_depth() -> None:
    ik = _nao_ik(IkCosts(foot=10.0, com=10.0, posture=1e-3, torso=1.0), torso="torso")
    ik.hold_frames()
    soles, com = _soles(ik), ik.configuration.data.subtree_com[1].copy()
    ik.com.set_target(com - np.array([0.0, 0.0, DEPTH_M]))
    stop = IkStop(tolerance_m=1e-6, max_iterations=400)
    errors = ik.solve(0.01, stop)
    lowered = ik.configuration.data.subtree_com[1]
    assert errors.com_m < stop.tolerance_m
    assert lowered[2] == pytest.approx(com[2] - DEPTH_M, abs=stop.tolerance_m)
    assert lowered[:2] == pytest.approx(com[:2], abs=stop.tolerance_m)
    assert np.max(np.linalg.norm(_soles(ik) - soles, axis=1)) < SOLE_HOLD_M
    assert errors.foot_m < SOLE_HOLD_M
    assert errors.torso_rad < 1e-3


def _lowering() -> WholeBodyIk:
    ik = _nao_ik(IkCosts(foot=10.0, com=10.0, posture=1e-3))
    ik.hold_frames()
    ik.com.set_target(ik.configuration.data.subtree_com[1] - np.array([0.0, 0.0, DEPTH_M]))
    return ik


def test_the_solve_stops_at_the_first_step_whose_watched_errors_are_within_tolerance() -> None:
    first = _lowering()
    one = first.solve(0.01, IkStop(tolerance_m=1e-6, max_iterations=1))
    assert math.isnan(one.torso_rad)  # no torso task to report
    tolerance_m = 0.5 * (one.com_m + one.foot_m)
    assert one.com_m < tolerance_m < one.foot_m  # one step: the CoM within, a sole not
    com_only, with_feet = _lowering(), _lowering()
    by_com = com_only.solve(0.01, IkStop(tolerance_m, max_iterations=50))
    by_both = with_feet.solve(0.01, IkStop(tolerance_m, max_iterations=50, watch_feet=True))
    assert by_com == one  # the CoM alone watched: the first step ends it
    assert np.array_equal(com_only.configuration.q, first.configuration.q)
    assert by_both.com_m < tolerance_m
    assert by_both.foot_m < tolerance_m  # the soles waited for


def test_the_crouch_of_a_users_robot_holds_its_soles_and_lowers_its_com(tmp_path: Path) -> None:
    file = draft_robot_file(write_biped_robot(tmp_path)).file
    assert file is not None
    model = mujoco.MjModel.from_xml_string(user_model(file).mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    sole_z = np.mean([data.site(sole_site(side)).xpos[2] for side in SIDES])
    standing_m = float(data.subtree_com[0][2] - sole_z)
    bent = crouch(model, file, 0.03)
    assert standing_m - bent.com_height_m == pytest.approx(0.03, abs=1e-4)
    assert any(abs(angle) > 0.1 for angle in bent.posture_rad.values())  # the knees bent
    apart = data.site(sole_site("left")).xpos - data.site(sole_site("right")).xpos
    for joint, angle in bent.posture_rad.items():
        data.qpos[model.joint(joint).qposadr[0]] = angle
    mujoco.mj_kinematics(model, data)
    bent_apart = data.site(sole_site("left")).xpos - data.site(sole_site("right")).xpos
    assert bent_apart == pytest.approx(apart, abs=SOLE_HOLD_M)  # the soles kept their places


def test_yaw_pose_is_a_turn_about_z_and_a_translation() -> None:
    pose = yaw_pose(0.1, -0.2, 0.3, 0.5)
    c, s = math.cos(0.5), math.sin(0.5)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    assert pose.rotation().as_matrix() == pytest.approx(rotation, abs=1e-15)
    assert pose.translation() == pytest.approx([0.1, -0.2, 0.3], abs=0.0)


def test_a_torso_task_needs_its_cost_and_its_body() -> None:
    message = r"a torso task needs both IkCosts\.torso and a torso_body"
    with pytest.raises(ModelError, match=message):
        _nao_ik(IkCosts(foot=10.0, com=10.0, posture=1e-3, torso=1.0))


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: IkStop(tolerance_m=1e-6, max_iterations=0), "max_iterations must be >= 1"),
        (lambda: IkStop(tolerance_m=0.0, max_iterations=1), "IkStop.tolerance_m"),
        (lambda: IkCosts(foot=10.0, com=-1.0, posture=1e-3), "IkCosts.com"),
    ],
)
def test_settings_out_of_range_are_named(make, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ParameterError, match=message):
        make()
