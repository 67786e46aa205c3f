"""The planned joint torques of the servo feed-forward against statics in closed form."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, cast

import mujoco
import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.robots.registry import get_robot
from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.servo_feedforward import (
    MIN_FOOT_SHARE,
    planned_joint_torques,
    servo_compliance_offsets,
)

FRAMES = 3
G = 9.81


def _static_walk(contact: dict[str, bool], zmp: str | None = None) -> tuple[Any, ...]:
    """The NAO standing still in its walking posture: a pattern stub and its trajectory."""
    walking = get_robot("nao").require_walking()
    settings, model = walking.ik_settings, mujoco.MjModel.from_xml_string(walking.ik_mjcf())
    joints = settings.joint_names
    q = np.array([settings.posture_rad.get(j, 0.0) for j in joints])
    base = np.array([0.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0])
    trajectory = JointTrajectory(
        np.arange(FRAMES) * 0.01, joints, np.tile(q, (FRAMES, 1)), np.tile(base, (FRAMES, 1)),
        np.zeros(FRAMES), np.zeros(FRAMES), np.zeros(FRAMES),
    )  # fmt: skip
    data = mujoco.MjData(model)
    data.qpos[:7] = base
    for name, angle in zip(joints, q, strict=True):
        data.qpos[model.joint(name).qposadr[0]] = angle
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    xy = np.zeros(2) if zmp is None else data.site(settings.sole_sites[zmp]).xpos[:2]
    feet = {s: SimpleNamespace(in_contact=np.full(FRAMES, contact[s])) for s in contact}
    pattern = SimpleNamespace(
        feet=SimpleNamespace(**feet), zmp_reference_in_world=np.tile(xy, (FRAMES, 1))
    )
    return cast(Any, pattern), trajectory, model, settings, data


def _subtree(model: mujoco.MjModel, body: int) -> set[int]:
    return {b for b in range(1, model.nbody) if _descends(model, b, body)}


def _descends(model: mujoco.MjModel, b: int, ancestor: int) -> bool:
    while b not in (0, ancestor):
        b = int(model.body_parentid[b])
    return b == ancestor


def _gravity_moment(model: mujoco.MjModel, data: mujoco.MjData, joint: str, bodies: set[int]):
    """Moment of the weight of ``bodies`` about ``joint``'s axis [N·m]."""
    jid = model.joint(joint).id
    anchor, axis = data.xanchor[jid], data.xaxis[jid]
    total = np.zeros(3)
    for b in bodies:
        total += np.cross(data.xipos[b] - anchor, [0.0, 0.0, -model.body_mass[b] * G])
    return float(total @ axis)


def _leg(joints: tuple[str, ...], prefix: str) -> list[str]:
    return [j for j in joints if j.startswith(prefix) and "Yaw" not in j]


def test_single_support_torques_are_the_statics_of_both_legs() -> None:
    """Stance leg: each joint holds the weight of everything above it; swing leg: below it."""
    pattern, trajectory, model, settings, data = _static_walk({"left": True, "right": False})
    model.opt.gravity[:] = (0.0, 0.0, -G)
    torques = planned_joint_torques(pattern, trajectory, model, settings)[1]
    every = set(range(1, model.nbody))
    for joint in _leg(trajectory.joint_names, "L"):
        below = _subtree(model, int(model.jnt_bodyid[model.joint(joint).id]))
        expected = _gravity_moment(model, data, joint, every - below)
        got = torques[trajectory.joint_names.index(joint)]
        assert got == pytest.approx(expected, rel=1e-6, abs=1e-9), joint
    for joint in _leg(trajectory.joint_names, "R"):
        below = _subtree(model, int(model.jnt_bodyid[model.joint(joint).id]))
        expected = -_gravity_moment(model, data, joint, below)
        got = torques[trajectory.joint_names.index(joint)]
        assert got == pytest.approx(expected, rel=1e-6, abs=1e-9), joint


def test_double_support_puts_the_weight_where_the_planned_zmp_is() -> None:
    single = _static_walk({"left": True, "right": False})
    double = _static_walk({"left": True, "right": True}, zmp="left")
    model = single[2]
    model.opt.gravity[:] = (0.0, 0.0, -G)
    double[2].opt.gravity[:] = (0.0, 0.0, -G)
    alone = planned_joint_torques(*single[:4])[1]
    shared = planned_joint_torques(*double[:4])[1]
    weight = float(np.sum(model.body_mass)) * G
    # the right foot keeps MIN_FOOT_SHARE of the least-norm split: torques within that share
    assert shared == pytest.approx(alone, abs=10 * MIN_FOOT_SHARE * weight * 0.3)


def test_offsets_are_the_torques_over_the_servo_stiffness() -> None:
    pattern, trajectory, model, settings, _ = _static_walk({"left": True, "right": True})
    torques = planned_joint_torques(pattern, trajectory, model, settings)
    offsets = servo_compliance_offsets(pattern, trajectory, model, settings, 20.0)
    assert offsets == pytest.approx(torques / 20.0)
    assert np.abs(torques).max() > 0.1  # the standing robot loads its legs
    with pytest.raises(ParameterError, match="stiffness_nm_per_rad"):
        servo_compliance_offsets(pattern, trajectory, model, settings, 0.0)
