r"""Walking defaults of a user's robot, derived from its model (robot file values first).

What the walk of :mod:`zmpkit.experiments.walk` needs of a robot, from the model zmpkit built
(:mod:`zmpkit.robots.user_model`) standing at its initial pose:

- **leg length** :math:`L`: height of the hip (the first leg joint's anchor) above the soles,
  mean of both legs [m];
- **crouch**: walking needs bent knees. The knee is the leg's pitch joint (axis along the
  world y) between the first and the last pitch joint nearest the middle of the leg; it is
  bent the way that moves the foot backward (a human knee), then a whole-body IK
  (:mod:`zmpkit.sim.whole_body_ik`: both soles held where they stand, the torso upright, a
  small pull to the seed) lowers the CoM by :data:`CROUCH_FRACTION` :math:`\times L`. Its leg
  joint angles are the IK's posture and its CoM height (above the soles) the walk's CoM height;
  the file's ``walking.torso_pitch`` leans the torso forward in the crouch and the walk, and
  its ``walking.zmp_forward`` moves the planned ZMP along each sole
  (:mod:`zmpkit.experiments.walking_posture` chooses both for ``robot init``);
- **foot separation**: the lateral distance between the sole centres [m];
- **step length limit**: :data:`STEP_LENGTH_FRACTION` :math:`\times L` [m];
- **sole**: the feet's footprint (or the file's ``sole``); **sole sites** ``zmpkit/{side}_sole``;
  **torso**: the file's ``torso`` (default: the root body);
- **IK model**: the simulation's own MJCF (rigid, every effect off): it carries the F-T sites
  ``zmpkit/{side}_ft`` and the IMU site ``zmpkit/imu`` under the names the simulation reads;
- **speed**, **servo stiffness and damping**, **observer σ_c and σ_p**: the file's
  (``speed``, ``servo_stiffness``, ``servo_damping``, ``observer_com_noise``,
  ``observer_zmp_noise``), else 0.2 m/s, none (servos that track), the observer's defaults.

A leg without a knee (fewer than three pitch joints) cannot walk: the robot then has no
walking defaults, and :func:`walking_problem` says why.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.robots.ik_settings import IkSettings
from zmpkit.robots.robot import DEFAULT_WALK_SPEED_MPS, WalkingDefaults
from zmpkit.robots.robot_file import SIDES, RobotFile
from zmpkit.robots.user_model import UserModel
from zmpkit.robots.user_model_file import root_body
from zmpkit.sim.names import sole_site
from zmpkit.sim.whole_body_ik import IkCosts, IkStop, WholeBodyIk, yaw_pose

__all__ = [
    "CONTROL_PERIOD_S",
    "CROUCH_FRACTION",
    "STEP_LENGTH_FRACTION",
    "Crouch",
    "crouch",
    "user_walking",
    "walking_problem",
]

CROUCH_FRACTION = 0.08
"""The walking crouch lowers the CoM by this share of the leg length [-] (the built-in
walking robot's crouch: hips about 8 % of its leg lower than straight)."""
STEP_LENGTH_FRACTION = 0.4
"""Largest forward step as a share of the leg length [-] (the built-in walking robot: 0.12 m
of about 0.3 m)."""
CONTROL_PERIOD_S = 0.01
"""Motion frame of a user's robot [s]: one IK solution per period."""
PITCH_AXIS_COSINE = 0.9
"""A joint is a pitch (roll) joint when its world axis is within acos(0.9) ≈ 26° of y (x)."""
_KNEE_SEED_RAD = 0.3
_IK_DT_S = 0.01
_CROUCH_COSTS = IkCosts(foot=10.0, com=10.0, posture=1e-3, torso=1.0)
_CROUCH_STOP = IkStop(tolerance_m=1e-5, max_iterations=400)


def _joint_axis(model: mujoco.MjModel, data: mujoco.MjData, name: str) -> NDArray[np.float64]:
    return np.asarray(data.xaxis[model.joint(name).id])


def axis_joints(
    model: mujoco.MjModel, data: mujoco.MjData, leg: tuple[str, ...], axis: int
) -> list[str]:
    """The leg's joints whose world axis lies along ``axis`` (0: x, roll; 1: y, pitch)."""
    return [j for j in leg if abs(_joint_axis(model, data, j)[axis]) >= PITCH_AXIS_COSINE]


def leg_length_m(model: mujoco.MjModel, data: mujoco.MjData, file: RobotFile) -> float:
    """Mean hip height (first leg joint's anchor) above the sole centres [m]."""
    heights = [
        float(data.xanchor[model.joint(file.legs[s][0]).id][2] - data.site(sole_site(s)).xpos[2])
        for s in SIDES
    ]
    return float(np.mean(heights))


def _knee(model: mujoco.MjModel, data: mujoco.MjData, leg: tuple[str, ...]) -> str | None:
    """The pitch joint between the hip's and the ankle's nearest the middle of the leg."""
    pitch = axis_joints(model, data, leg, 1)
    if len(pitch) < 3:
        return None
    z = [float(data.xanchor[model.joint(j).id][2]) for j in pitch]
    middle = 0.5 * (z[0] + z[-1])
    inner = pitch[1:-1]
    return min(inner, key=lambda j: abs(z[pitch.index(j)] - middle))


def pitch_joints(model: mujoco.MjModel, data: mujoco.MjData, file: RobotFile) -> tuple[str, ...]:
    """Hip pitch, knee and ankle pitch of the left leg, then the right leg."""
    out: list[str] = []
    for side in ("left", "right"):
        pitch = axis_joints(model, data, file.legs[side], 1)
        knee = _knee(model, data, file.legs[side])
        assert knee is not None  # walking_problem was None
        out += [pitch[0], knee, pitch[-1]]
    return tuple(out)


def walking_problem(file: RobotFile, built: UserModel) -> str | None:
    """Why the robot cannot walk (a leg without a knee), or None."""
    model = mujoco.MjModel.from_xml_string(built.mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    for side in SIDES:
        if _knee(model, data, file.legs[side]) is None:
            return f"legs.{side} has no knee (a pitch joint between the hip and the ankle)"
    return None


@dataclass(frozen=True)
class Crouch:
    """The walking crouch of a model (module docstring).

    Attributes:
        posture_rad: leg joint → angle [rad].
        com_height_m: CoM height above the soles [m].
    """

    posture_rad: Mapping[str, float]
    com_height_m: float


def _seed(model: mujoco.MjModel, file: RobotFile) -> NDArray[np.float64]:
    """The initial pose with each knee bent the human way (foot moves backward)."""
    data = mujoco.MjData(model)
    q = model.qpos0.copy()
    data.qpos[:] = q
    mujoco.mj_forward(model, data)
    for side in SIDES:
        knee = _knee(model, data, file.legs[side])
        assert knee is not None  # walking_problem was None
        adr = int(model.joint(knee).qposadr[0])
        before = float(data.site(sole_site(side)).xpos[0])
        probe = mujoco.MjData(model)
        probe.qpos[:] = q
        probe.qpos[adr] += _KNEE_SEED_RAD
        mujoco.mj_forward(model, probe)
        sign = 1.0 if float(probe.site(sole_site(side)).xpos[0]) < before else -1.0
        q[adr] += sign * _KNEE_SEED_RAD
    return q


def crouch(
    model: mujoco.MjModel, file: RobotFile, depth_m: float, torso_pitch_rad: float = 0.0
) -> Crouch:
    """Lower the standing CoM by ``depth_m`` [m] with the soles fixed and the torso upright.

    Args:
        model: the robot's model at its standing pose (``qpos0``), soles on the floor.
        file: the robot file (legs, torso).
        depth_m: how far the CoM goes down [m].
        torso_pitch_rad: the torso's forward lean [rad] (0: upright, as the walk holds it).
    """
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    sole_sites = {side: sole_site(side) for side in SIDES}
    torso = file.torso or root_body(model)
    ik = WholeBodyIk(model, model.qpos0.copy(), sole_sites, _CROUCH_COSTS, torso_body=torso)
    ik.hold_frames()
    if torso_pitch_rad != 0.0:
        assert ik.torso is not None  # _CROUCH_COSTS has a torso weight
        ik.torso.set_target(yaw_pose(0.0, 0.0, 0.0, 0.0, torso_pitch_rad))
    ik.com.set_target(np.asarray(data.subtree_com[0]) - np.array([0.0, 0.0, depth_m]))
    ik.restart(_seed(model, file))
    ik.solve(_IK_DT_S, _CROUCH_STOP)
    config = ik.configuration
    sole_z = np.mean([config.data.site(sole_site(s)).xpos[2] for s in SIDES])
    angles = {j: float(config.q[int(model.joint(j).qposadr[0])]) for j in file.leg_joints}
    return Crouch(angles, float(config.data.subtree_com[0][2] - sole_z))


def user_walking(file: RobotFile, built: UserModel) -> WalkingDefaults | None:
    """The walking defaults of a user's robot (module docstring), or None if it cannot walk.

    ``walking.posture``'s joints are leg joints (checked with the model's names:
    :func:`~zmpkit.robots.user_model_names.name_problems`).
    """
    if walking_problem(file, built) is not None:
        return None
    given = file.walking
    model = mujoco.MjModel.from_xml_string(built.mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    leg = leg_length_m(model, data, file)
    pitch = given.torso_pitch_rad or 0.0
    bent = crouch(model, file, (given.crouch or CROUCH_FRACTION) * leg, pitch)
    posture = dict(given.posture_rad) if given.posture_rad is not None else bent.posture_rad
    sole = [data.site(sole_site(s)).xpos for s in SIDES]
    separation = float(abs(sole[1][1] - sole[0][1]))
    feet = built.feet
    return WalkingDefaults(
        com_height_m=given.com_height_m or bent.com_height_m,
        control_period_s=given.control_period_s or CONTROL_PERIOD_S,
        foot_separation_m=given.foot_separation_m or separation,
        max_step_length_m=given.max_step_length_m or STEP_LENGTH_FRACTION * leg,
        sole_size_m=(
            min(f.length_m for f in feet.values()),
            min(f.width_m for f in feet.values()),
        ),
        ik_settings=IkSettings(
            joint_names=file.leg_joints,
            sole_sites={side: sole_site(side) for side in ("left", "right")},
            torso_body=file.torso or root_body(model),
            torso_pitch_rad=pitch,
            posture_rad=posture,
        ),
        ik_mjcf=lambda: built.mjcf,
        series_joints=pitch_joints(model, data, file),
        speed_mps=given.speed_mps or DEFAULT_WALK_SPEED_MPS,
        servo_stiffness_nm_per_rad=given.servo_stiffness_nm_per_rad,
        servo_damping_nm_s_per_rad=given.servo_damping_nm_s_per_rad or 0.0,
        observer_com_noise_m=given.observer_com_noise_m,
        observer_zmp_noise_m=given.observer_zmp_noise_m,
        zmp_forward_m=given.zmp_forward_m or 0.0,
    )
