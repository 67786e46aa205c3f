"""A simulation frozen where a batch starts from it: its state and sensor channels, no MjData.

A batch of candidates sharing one compiled model is posed on one
:class:`~zmpkit.sim.world.Simulation`, candidate after candidate
(:meth:`~zmpkit.sim.world.Simulation.restart`: a new MjData costs ~0.3 ms, a reset nothing).
What a batch reads of each candidate's posed simulation afterwards is kept in a
:class:`PosedSimulation`: the state (:class:`PosedData`: ``mjSTATE_FULLPHYSICS``, ``qpos``,
``sensordata``, the site kinematics), its F-T channels and servo, and its description; the
model's layout (sensor addresses, joints, actuator gears) is the shared simulation's. It reads
as that simulation read right after the pose (tested).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypeAlias

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.sim.description import RobotDescription
from zmpkit.sim.sensing import FtChannel
from zmpkit.sim.servo import TrajectoryLimiter
from zmpkit.sim.world import Simulation, encoder_angles

__all__ = ["PosedData", "PosedSimulation", "StartedSimulation"]

_FULL = mujoco.mjtState.mjSTATE_FULLPHYSICS


@dataclass(frozen=True)
class PosedData:
    """The MjData arrays a batch reads of a posed simulation (copies).

    Attributes:
        time: simulated time [s].
        qpos: ``(nq,)`` generalised positions [m, rad, quaternion].
        sensordata: ``(nsensordata,)`` noiseless sensor readings [MuJoCo units].
        site_xpos: ``(nsite, 3)`` site positions, world frame [m].
        site_xmat: ``(nsite, 9)`` site orientations, row-major [-].
        state: the ``mjSTATE_FULLPHYSICS`` state (time, qpos, qvel, act, ...).
    """

    time: float
    qpos: NDArray[np.float64]
    sensordata: NDArray[np.float64]
    site_xpos: NDArray[np.float64]
    site_xmat: NDArray[np.float64]
    state: NDArray[np.float64]

    @classmethod
    def of(cls, model: mujoco.MjModel, data: mujoco.MjData) -> PosedData:
        """Copies of ``data``'s arrays now."""
        state = np.empty(mujoco.mj_stateSize(model, _FULL))
        mujoco.mj_getState(model, data, state, _FULL)
        return cls(
            float(data.time),
            data.qpos.copy(),
            data.sensordata.copy(),
            data.site_xpos.copy(),
            data.site_xmat.copy(),
            state,
        )


class PosedSimulation:
    """A candidate's simulation as it stood after its pose, read-only.

    Args:
        layout: the simulation it was posed on (its model's layout is shared; its state,
            channels and servo have moved on since).
        robot: the candidate's description.
        data: its posed state.
        channels: foot -> its F-T channel, as sampled up to the pose.
        servo: its servo, as after the pose.
    """

    def __init__(
        self,
        layout: Simulation,
        robot: RobotDescription,
        data: PosedData,
        channels: dict[str, FtChannel],
        servo: TrajectoryLimiter,
    ) -> None:
        self.robot = robot
        self.model = layout.model
        self.data = data
        self.dt = layout.dt
        self.servo = servo
        self._layout = layout
        self._channels = channels

    @classmethod
    def taken_from(cls, sim: Simulation) -> PosedSimulation:
        """``sim`` as it stands, its channels and servo handed over (restart it after)."""
        channels = {f.foot: sim.ft_channel(f.foot) for f in sim.robot.feet}
        return cls(sim, sim.robot, PosedData.of(sim.model, sim.data), channels, sim.servo)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The driven joints, in the order of commands and encoder readings."""
        return self.robot.driven_joints

    @property
    def ft_sample_every(self) -> int:
        """Physics steps between two F-T samples [-]."""
        return self._layout.ft_sample_every

    def ft_channel(self, foot: str) -> FtChannel:
        """``foot``'s F-T channel (its state: the last sample before the batch)."""
        return self._channels[foot]

    def encoders_of(self, qpos: NDArray[np.float64]) -> NDArray[np.float64]:
        """:meth:`Simulation.encoders_of <zmpkit.sim.world.Simulation.encoders_of>` [rad]."""
        return encoder_angles(qpos, self._layout.joint_qpos_addresses, self.robot)

    def ft_true_of(self, foot: str, sensordata: NDArray[np.float64]) -> NDArray[np.float64]:
        """The true wrench of ``foot`` in recorded ``sensordata`` rows [N, N·m]."""
        return self._layout.ft_true_of(foot, sensordata)

    def sensor_slice(self, name: str) -> slice:
        """Where MuJoCo sensor ``name`` sits in ``sensordata``."""
        return self._layout.sensor_slice(name)

    def controls_of(self, setpoints: NDArray[np.float64]) -> NDArray[np.float64]:
        """Actuator controls of servo setpoints [rad] (the shared model's gears)."""
        return self._layout.controls_of(setpoints)


StartedSimulation: TypeAlias = Simulation | PosedSimulation
"""Where a batch's candidate starts: its own simulation, or one frozen after its pose."""
