"""Whole-body inverse kinematics of a walking pattern (differential IK on MuJoCo, with mink).

At every sample of the pattern (every motion frame, e.g. 10 ms) the IK drives the robot model to

- both sole-centre frames at the planned foot poses (position and yaw; flat on the ground),
- the torso upright with the planned torso yaw (orientation only),
- the whole-body CoM at the planned CoM ``(x, y, z_c)``,
- and, with a small weight, a nominal posture (which fixes the redundant directions),

subject to the joint limits and to the model's joint equalities (e.g. two hip joints driven by
one motor).
The solver is :class:`~zmpkit.sim.whole_body_ik.WholeBodyIk`, zmpkit's one mink set-up.
Each sample is warm-started from the previous solution and iterated until the CoM and feet
errors fall below :attr:`IkSettings.tolerance_m` or :attr:`IkSettings.max_iterations` is
spent. The footstep planner's foot point is the *sole centre*; the model must carry a site
there (an ankle may lie behind it), so the ankle offset is the model's geometry.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Protocol

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError
from zmpkit.robots.ik_settings import IkSettings
from zmpkit.sim.whole_body_ik import IkCosts, IkStop, WholeBodyIk, yaw_pose
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.swing import FeetTrajectories

__all__ = ["IkSettings", "JointTrajectory", "WalkingIk", "solve_walking_ik"]


@dataclass(frozen=True)
class JointTrajectory:
    """Joint angles that realise a walking pattern on a model, with the errors left.

    Attributes:
        time_s: sample times [s], shape (N,).
        joint_names: names of the columns of ``q_rad``.
        q_rad: joint angles [rad], shape (N, J).
        base_qpos: floating-base pose (x, y, z, qw, qx, qy, qz) the IK found, shape (N, 7).
        com_error_m: CoM position error after the IK [m], shape (N,).
        foot_error_m: largest sole-centre position error of both feet [m], shape (N,).
        torso_error_rad: torso orientation error [rad], shape (N,).
    """

    time_s: NDArray[np.float64]
    joint_names: tuple[str, ...]
    q_rad: NDArray[np.float64]
    base_qpos: NDArray[np.float64]
    com_error_m: NDArray[np.float64]
    foot_error_m: NDArray[np.float64]
    torso_error_rad: NDArray[np.float64]

    @property
    def max_com_error_m(self) -> float:
        """Largest CoM error over the walk [m]."""
        return float(np.max(self.com_error_m))

    @property
    def max_foot_error_m(self) -> float:
        """Largest foot position error over the walk [m]."""
        return float(np.max(self.foot_error_m))

    @property
    def max_torso_error_rad(self) -> float:
        """Largest torso orientation error over the walk [rad]."""
        return float(np.max(self.torso_error_rad))

    def joint(self, name: str) -> NDArray[np.float64]:
        """One joint's angles [rad], shape (N,)."""
        if name not in self.joint_names:
            raise ModelError(f"unknown joint {name!r}; joints: {list(self.joint_names)}")
        return self.q_rad[:, self.joint_names.index(name)]


class IkTargets(Protocol):
    """What :meth:`WalkingIk.set_targets` reads: a :class:`WalkingPattern`, or online targets."""

    @property
    def feet(self) -> FeetTrajectories: ...

    @property
    def com_position_in_world(self) -> NDArray[np.float64]: ...


class WalkingIk:
    """The whole-body IK of one model, re-targeted sample after sample.

    For online use, e.g. a compensation that changes the CoM plan while walking. The solver
    is :class:`~zmpkit.sim.whole_body_ik.WholeBodyIk` with the settings' weights; this class
    adds the walk's targets and reports its joints.
    """

    def __init__(self, model: mujoco.MjModel, settings: IkSettings) -> None:
        self.settings = settings
        self.model = model
        self.body = WholeBodyIk(
            model,
            _start_q(model, settings),
            settings.sole_sites,
            IkCosts(
                foot=settings.foot_cost,
                com=settings.com_cost,
                posture=settings.posture_cost,
                torso=settings.torso_cost,
                equality=settings.equality_cost,
            ),
            torso_body=settings.torso_body,
            solver=settings.solver,
            damping=settings.damping,
        )
        self.configuration = self.body.configuration
        self.foot_pitch_rad = np.zeros(len(self.body.feet))
        """Each sole's pitch target [rad], in the order of :attr:`feet` (nose down positive;
        0: parallel to the ground)."""
        self.feet = tuple(self.body.feet)
        """The soles' sides, in the order of :attr:`foot_pitch_rad`."""
        self._stop = IkStop(settings.tolerance_m, settings.max_iterations, watch_feet=True)
        self.qadr = [_qpos_address(model, name) for name in settings.joint_names]

    def set_targets(self, pattern: IkTargets, k: int) -> None:
        """Aim the tasks at sample ``k`` of ``pattern``: feet [m, rad], torso yaw [rad], CoM [m]."""
        feet, body = pattern.feet, self.body
        for i, (side, task) in enumerate(body.feet.items()):
            trajectory = feet.left if side == "left" else feet.right
            x, y, z = trajectory.position_in_world[k]
            pitch = self.foot_pitch_rad.item(i)
            task.set_target(yaw_pose(x, y, z, trajectory.yaw_in_world[k], pitch))
        assert body.torso is not None  # IkCosts.torso is always given
        pitch = self.settings.torso_pitch_rad
        body.torso.set_target(yaw_pose(0.0, 0.0, 0.0, feet.torso_yaw_in_world[k], pitch))
        body.com.set_target(pattern.com_position_in_world[k])

    def errors(self) -> tuple[float, float, float]:
        """CoM [m], largest foot position [m] and torso orientation [rad] errors."""
        e = self.body.errors()
        return e.com_m, e.foot_m, e.torso_rad

    def solve(self, iterations: int, dt: float) -> tuple[float, float, float]:
        """Integrate up to ``iterations`` IK steps of ``dt`` [s] and return the errors.

        Stops early once the CoM and foot errors are below the tolerance [m]; the errors are
        those of :meth:`errors`: CoM [m], largest foot position [m], torso orientation [rad].
        """
        stop = self._stop
        if iterations != stop.max_iterations:
            stop = replace(stop, max_iterations=iterations)
        e = self.body.solve(dt, stop)
        return e.com_m, e.foot_m, e.torso_rad


def _qpos_address(model: mujoco.MjModel, name: str) -> int:
    joint_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
    if joint_id < 0:
        raise ModelError(f"the IK model has no joint {name!r}")
    return int(model.jnt_qposadr[joint_id])


def _start_q(model: mujoco.MjModel, settings: IkSettings) -> NDArray[np.float64]:
    q = model.qpos0.copy()
    for name, angle in settings.posture_rad.items():
        q[_qpos_address(model, name)] = angle
    return q


def solve_walking_ik(
    pattern: WalkingPattern,
    model: mujoco.MjModel,
    settings: IkSettings,
) -> JointTrajectory:
    """Joint angles that realise ``pattern`` on ``model``, one IK solution per sample.

    Args:
        pattern: the walk (feet, torso yaw and CoM on one time grid).
        model: the robot's rigid kinematic model, floating base first, with a site at each
            sole centre (see :class:`IkSettings`).
        settings: joints, frames, weights and stopping rule (a robot's
            :attr:`~zmpkit.robots.robot.Robot.ik_settings`).

    Returns:
        The joint trajectory with the CoM, feet and torso errors left at each sample.
    """
    ik = WalkingIk(model, settings)
    n = pattern.time_s.size
    q = np.empty((n, len(settings.joint_names)))
    base = np.empty((n, 7))
    errors = np.empty((n, 3))
    dt = pattern.config.control_period_s
    for k in range(n):
        ik.set_targets(pattern, k)
        iterations = settings.max_iterations * (10 if k == 0 else 1)
        errors[k] = ik.solve(iterations, dt)
        q[k] = ik.configuration.q[ik.qadr]
        base[k] = ik.configuration.q[:7]
    return JointTrajectory(
        time_s=pattern.time_s.copy(),
        joint_names=settings.joint_names,
        q_rad=q,
        base_qpos=base,
        com_error_m=errors[:, 0],
        foot_error_m=errors[:, 1],
        torso_error_rad=errors[:, 2],
    )
