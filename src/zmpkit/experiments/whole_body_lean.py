r"""The balance lean of any robot: whole-body IK, both soles fixed, the CoM moved.

Statically the ZMP is the ground projection of the CoM, so a robot standing on both feet
brings its ZMP to a target :math:`x_{ref}` by moving its CoM there. With :math:`l` the
standing CoM height above the lean's pivots (the ankle pitch joints for the sagittal plane,
the ankle roll joints for the frontal plane) and :math:`c_0` the standing CoM, the lean angle
:math:`\theta` asks the IK for the CoM

.. math:: c(\theta) = c_0 + l \sin\theta \, e + l (\cos\theta - 1) \, e_z,

(:math:`e` the plane's horizontal axis), the path of a rigid pendulum of length :math:`l` about
the pivots, so :math:`x_{exp}(\theta) = l \sin\theta` as for the ankle strategy
(:mod:`zmpkit.experiments.lean`). The IK (:mod:`zmpkit.sim.whole_body_ik`) has these tasks:
both sole-centre sites at their standing poses, the whole-body CoM at :math:`c(\theta)`, and a
small pull to the standing posture (which picks the ankle-led solution among the redundant
ones). The joint angles are solved once on a grid of
:math:`\theta` and interpolated linearly.

:meth:`WholeBodyLean.angle_joints` gives the pivot joints with :math:`s_j = 1 / (\partial q_j /
\partial\theta)` at the standing pose, so :math:`\theta \approx \operatorname{mean}_j s_j q_j`
(to first order; the lean's joints are taken as zero at the standing pose).

Design knowledge only: the rigid model (effects off) at its standing pose.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ModelError
from zmpkit.robots.robot import Robot
from zmpkit.sim.names import sole_site
from zmpkit.sim.whole_body_ik import IkCosts, IkStop, WholeBodyIk
from zmpkit.sim.world import Simulation

__all__ = ["LEAN_RANGE_RAD", "WholeBodyLean", "whole_body_lean"]

LEAN_RANGE_RAD = 0.4
"""The lean is solved for :math:`|\\theta| \\le` this [rad] (a ZMP up to 39 % of ``l``)."""
_GRID_POINTS = 21  # per side of zero
_IK_DT_S = 0.01
_COSTS = IkCosts(foot=10.0, com=10.0, posture=1e-2)
_STOP = IkStop(tolerance_m=1e-6, max_iterations=300)
_AXIS = {"sagittal": 0, "frontal": 1}


@dataclass(frozen=True, eq=False)
class WholeBodyLean:
    r"""The whole-body lean of a design model in one plane (module docstring).

    Attributes:
        plane: ``"sagittal"`` or ``"frontal"``.
        lean_length_m: :math:`l`, the standing CoM height above the pivots [m].
        pivots: the pivot joints (right, left) that measure :math:`\theta`.
        grid_rad: the lean angles solved [rad], shape (G,).
        angles_rad: joint → its angle at each grid angle [rad], shape (G,).
        com_error_m: largest CoM error the IK left over the grid [m].
    """

    plane: str
    lean_length_m: float
    pivots: tuple[str, str]
    grid_rad: NDArray[np.float64]
    angles_rad: Mapping[str, NDArray[np.float64]]
    com_error_m: float

    def joint_targets(self, angle_rad: float) -> dict[str, float]:
        """Joint angles [rad] that lean the design robot by ``angle_rad`` [rad], soles flat."""
        return {
            j: float(np.interp(angle_rad, self.grid_rad, v)) for j, v in self.angles_rad.items()
        }

    def angle_joints(self) -> dict[str, float]:
        r"""The pivots and ``s_j`` with :math:`\theta \approx \operatorname{mean}_j s_j q_j`."""
        mid = len(self.grid_rad) // 2
        step = float(self.grid_rad[mid + 1] - self.grid_rad[mid - 1])
        out = {}
        for pivot in self.pivots:
            q = self.angles_rad[pivot]
            slope = float(q[mid + 1] - q[mid - 1]) / step
            if abs(slope) < 1e-3:
                raise ModelError(f"the {self.plane} lean does not move the pivot joint {pivot!r}")
            out[pivot] = 1.0 / slope
        return out


def _lean_length(sim: Simulation, pivots: tuple[str, str]) -> float:
    m, d = sim.model, sim.data
    pivot_z = np.mean([d.xanchor[m.joint(j).id][2] for j in pivots])
    return float(d.subtree_com[0][2] - pivot_z)


def whole_body_lean(robot: Robot, plane: str) -> WholeBodyLean:
    """Solve the whole-body lean of ``robot``'s design model in ``plane`` (module docstring).

    Raises:
        ModelError: if the lean does not move the pivot joints.
    """
    balance = robot.require_balance()
    pivots = balance.require_plane(plane)
    sim = robot.make_simulation("none")
    model, standing = sim.model, sim.data.qpos.copy()
    length = _lean_length(sim, pivots)
    c0 = np.array(sim.data.subtree_com[0])
    soles = {foot.foot: sole_site(foot.foot) for foot in sim.robot.feet}
    ik = WholeBodyIk(model, standing, soles, _COSTS)
    ik.hold_frames()
    axis = np.zeros(3)
    axis[_AXIS[plane]] = 1.0
    half = np.linspace(0.0, LEAN_RANGE_RAD, _GRID_POINTS + 1)
    joints = sim.joint_names
    adr = [int(model.joint(j).qposadr[0]) for j in joints]
    rows: dict[float, NDArray[np.float64]] = {}
    worst = 0.0
    for sign in (1.0, -1.0):
        ik.restart(standing)
        for theta in sign * half:
            target = c0 + length * (np.sin(theta) * axis + (np.cos(theta) - 1.0) * np.eye(3)[2])
            ik.com.set_target(target)
            worst = max(worst, ik.solve(_IK_DT_S, _STOP).com_m)
            rows[float(theta)] = ik.configuration.q[adr].copy()
    grid = np.array(sorted(rows))
    table = np.array([rows[float(t)] for t in grid])
    angles = {j: table[:, k] for k, j in enumerate(joints)}
    return WholeBodyLean(plane, length, pivots, grid, angles, worst)
