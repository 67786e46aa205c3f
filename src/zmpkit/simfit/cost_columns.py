"""What of a rollout the fit's cost reads: the few columns recorded, and the joint term's sum.

The cost (:mod:`~zmpkit.simfit.cost`) reads, per recorded row, the encoders of the
experiment's joints, the ZMP from the feet's F-T sensors and their sites' poses, and the
IMU's trunk tilt; a walk's fall rule reads the torso height and the IMU too. On MuJoCo Warp
only those columns are recorded (:class:`CostColumns`): the floating base's height, the F-T
force and torque of each foot and the IMU quaternion of ``sensordata``, and the F-T sites'
poses. The joint term is a sum of squared differences against the recorded encoders at
known rows, so it is summed per world on the device
(:class:`~zmpkit.sim.warp_columns.QposSquareError`) and only that sum comes back.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.sim.posed import StartedSimulation
from zmpkit.sim.warp_columns import QposSquareError

__all__ = ["HEIGHT_QPOS", "CostColumns", "cost_columns", "joint_square_error"]

HEIGHT_QPOS = 2
"""The qpos entry of the floating base's height [m] (a walk's fall rule)."""


@dataclass(frozen=True)
class CostColumns:
    """The columns of a rollout's arrays the cost reads, and where they land in a row.

    Attributes:
        qpos: qpos entries kept: the floating base's height [m].
        sensordata: sensordata entries kept: each foot's F-T force then torque (3 + 3, in
            foot order) [N, N·m], then the IMU orientation quaternion (w, x, y, z).
        sites: the F-T sites (foot order) whose poses are kept.
        nfeet: number of feet [-].
    """

    qpos: tuple[int, ...]
    sensordata: tuple[int, ...]
    sites: tuple[int, ...]
    nfeet: int

    @property
    def ft_positions(self) -> NDArray[np.int64]:
        """``(feet, 6)`` where each foot's force and torque sit in a kept sensordata row."""
        return np.arange(6 * self.nfeet).reshape(self.nfeet, 6)

    @property
    def quat_positions(self) -> NDArray[np.int64]:
        """``(4,)`` where the IMU quaternion sits in a kept sensordata row."""
        return 6 * self.nfeet + np.arange(4)

    def as_mapping(self) -> dict[str, tuple[int, ...]]:
        """The ``columns`` argument of :func:`~zmpkit.sim.warp_batch.rollout_warp`."""
        return {
            "qpos": self.qpos,
            "sensordata": self.sensordata,
            "site_xpos": self.sites,
            "site_xmat": self.sites,
        }


def cost_columns(sim: StartedSimulation) -> CostColumns:
    """The columns of ``sim``'s model the cost reads (module docstring)."""
    robot = sim.robot
    sensors: list[int] = []
    for foot in robot.feet:
        for name in (foot.force_sensor, foot.torque_sensor):
            s = sim.sensor_slice(name)
            sensors += range(s.start, s.stop)
    quat = sim.sensor_slice(robot.imu.orientation)
    sensors += range(quat.start, quat.stop)
    sites = tuple(int(sim.model.site(foot.site).id) for foot in robot.feet)
    return CostColumns((HEIGHT_QPOS,), tuple(sensors), sites, len(robot.feet))


def joint_square_error(
    sims: Sequence[StartedSimulation],
    joints: Sequence[Sequence[str]],
    steps: Sequence[NDArray[np.int64]],
    targets: Sequence[NDArray[np.float64]],
) -> QposSquareError:
    """The joint term's sum for a batch of experiments (one control group each).

    The experiments' joints may differ: the columns are their union (in first-seen order)
    and a group's targets are NaN in the columns it does not compare.

    Args:
        sims: one simulation of each group (its encoders' joints and resolution).
        joints: each group's compared joints.
        steps: each group's rollout steps of its rows (1 is after the first).
        targets: each group's recorded encoders at those rows, ``(R_g, J_g)`` [rad].
    """
    model = sims[0].model
    union = list(dict.fromkeys(j for names in joints for j in names))
    columns = tuple(int(model.jnt_qposadr[model.joint(j).id]) for j in union)
    robot = sims[0].robot
    step = float(robot.sensor_params.encoder_resolution) if robot.effects.sensors else 0.0
    table = []
    for names, target in zip(joints, targets, strict=True):
        full = np.full((len(target), len(union)), np.nan)
        full[:, [union.index(j) for j in names]] = target
        table.append(full)
    return QposSquareError(
        columns,
        tuple(np.asarray(s, dtype=np.int64) for s in steps),
        tuple(table),
        (step,) * len(union),
    )
