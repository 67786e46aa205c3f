"""A running simulation: MuJoCo model and data, joint servos, sensor effects, divergence check.

The world steps at a fixed timestep (the robot's servo period). Each physics step the
servo trajectories advance one tick and write the actuator setpoints; the F-T sensors are
sampled at their own rate. Readings are what a user of the real robot gets:

- :meth:`Simulation.ft` — each foot's wrench ``(Fx, Fy, Fz, Tx, Ty, Tz)`` [N, N·m] that the
  sole applies to the robot above the sensor, in the sensor frame (x forward, y left, z up),
  so ``Fz > 0`` when loaded; with S on, sampled with offset, gain, noise, filter, quantum.
- :meth:`Simulation.encoders` — motor-side joint angles / N [rad] (what the encoder sees;
  gear deflection and structural flex are invisible), quantised with S on.
- :meth:`Simulation.imu` — gyro [rad/s], accelerometer [m/s²] (noisy with S on) and the
  orientation quaternion (w, x, y, z).

A step whose accelerations are not finite, that trips MuJoCo's bad-qacc warning, or whose
joint speed exceeds :data:`DIVERGED_SPEED_RAD_S` raises
:class:`~zmpkit.errors.SimulationDivergedError` with the time and the joint.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError, SimulationDivergedError
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.sensing import FtChannel, quantise
from zmpkit.sim.servo import TrajectoryLimiter

__all__ = ["DIVERGED_SPEED_RAD_S", "Simulation", "encoder_angles"]

DIVERGED_SPEED_RAD_S = 200.0
"""A generalised velocity beyond this [rad/s or m/s] counts as divergence."""


class Simulation:
    """The simulated robot.

    Args:
        robot: the robot description (MJCF with effects applied and sensor names).
        seed: seed of every noise stream; the same seed gives identical readings.
        model: ``robot.mjcf`` already compiled, used as it is (the simulation owns it from
            then on: pass a copy to share one compilation among simulations, as a fit
            does for one candidate's experiments); None compiles it.
    """

    def __init__(
        self, robot: RobotDescription, seed: int = 0, model: mujoco.MjModel | None = None
    ) -> None:
        self.robot = robot
        self.model = mujoco.MjModel.from_xml_string(robot.mjcf) if model is None else model
        self.data = mujoco.MjData(self.model)
        self.dt = float(self.model.opt.timestep)
        self._act = [self.model.actuator(j).id for j in robot.driven_joints]
        self._gear = [float(self.model.actuator_gear[i, 0]) for i in self._act]
        self._qadr = [
            int(self.model.jnt_qposadr[self.model.joint(j).id]) for j in robot.driven_joints
        ]
        self._sens = {
            f.foot: self._sensor_slices(f.force_sensor, f.torque_sensor) for f in robot.feet
        }
        self._streams: tuple[tuple[int, int], list[np.random.SeedSequence]] = ((-1, 0), [])
        self._start(seed)

    def restart(self, robot: RobotDescription, seed: int = 0) -> None:
        """Start again at the model's initial state, as a new simulation of ``robot`` would.

        ``robot`` differs from the current description in its sensor errors only (same
        MJCF, joints and feet; e.g. a fit candidate's F-T offsets), and the model's fields
        may have been rewritten since (a candidate's, :mod:`zmpkit.sim.world_fields`). The
        data is reset in place (no allocation: a new MjData costs ~0.3 ms) and the sensor
        channels, servo and step count are new; the state and readings are then those of
        ``Simulation(robot, seed, model)``, bit for bit (tested).
        """
        self.robot = robot
        mujoco.mj_resetData(self.model, self.data)
        self._start(seed)

    def _start(self, seed: int) -> None:
        """The state of a simulation just built: noise streams, channels, servo, first sample."""
        robot = self.robot
        key = (seed, len(robot.feet) + 1)
        if self._streams[0] != key:  # the same children every time (generate_state is pure)
            self._streams = (key, np.random.SeedSequence(seed).spawn(key[1]))
        streams = self._streams[1]
        self._imu_stream = streams[-1]
        self._imu_rng_now: np.random.Generator | None = None  # made on first use
        params = robot.sensor_params
        self._ft = {
            f.foot: FtChannel(
                params,
                robot.ft_offset(f.foot),
                np.random.default_rng(s),
                robot.ft_gain_error(f.foot),
            )
            for f, s in zip(robot.feet, streams[:-1], strict=True)
        }
        self._ft_every = max(1, round(1.0 / (params.ft_rate_hz * self.dt)))
        self._steps = 0
        self.servo = TrajectoryLimiter([0.0] * len(self._act), robot.servo_limits, self.dt)
        mujoco.mj_forward(self.model, self.data)
        self._sample_ft()

    def _sensor_slices(self, force: str, torque: str) -> tuple[slice, slice]:
        return self.sensor_slice(force), self.sensor_slice(torque)

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self.data.time)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The driven joints, in the order of commands and encoder readings."""
        return self.robot.driven_joints

    def command(self, q_ref: Sequence[float] | Mapping[str, float]) -> None:
        """Give the servos new joint targets [rad] (a sequence in joint order, or by name).

        Joints missing from a mapping keep their current target.
        """
        if isinstance(q_ref, Mapping):
            unknown = set(q_ref) - set(self.joint_names)
            if unknown:
                raise ParameterError(
                    f"unknown joints {sorted(unknown)}; driven joints: {list(self.joint_names)}"
                )
            target = [
                float(q_ref.get(n, t))
                for n, t in zip(self.joint_names, self.servo.target, strict=True)
            ]
        else:
            target = [float(q) for q in q_ref]
        self.servo.set_target(target)

    def step(self, n: int = 1) -> None:
        """Advance ``n`` physics steps."""
        model, data = self.model, self.data
        warn = data.warning[mujoco.mjtWarning.mjWARN_BADQACC]
        remaining = n
        while remaining > 0:
            setpoints = self.servo.tick()
            ctrl = data.ctrl
            for i, g, q in zip(self._act, self._gear, setpoints, strict=True):
                ctrl[i] = g * q
            # Setpoints held still stay still until the next sensor sample: step there in C.
            to_sample = self._ft_every - self._steps % self._ft_every
            chunk = 1 if self.servo.moving else min(remaining, to_sample)
            bad = warn.number
            mujoco.mj_step(model, data, nstep=chunk)
            self._steps += chunk
            remaining -= chunk
            if warn.number != bad:
                self._diverged("MuJoCo reported bad accelerations (bad qacc)")
            if self._steps % self._ft_every == 0:
                self._check_speed()
                self._sample_ft()

    def run(self, seconds: float) -> None:
        """Advance by ``seconds`` of simulated time [s]."""
        self.step(max(0, round(seconds / self.dt)))

    def _check_speed(self) -> None:
        qvel = self.data.qvel
        if not np.all(np.isfinite(qvel)) or np.max(np.abs(qvel)) > DIVERGED_SPEED_RAD_S:
            self._diverged(f"joint speed beyond {DIVERGED_SPEED_RAD_S} rad/s")

    def _diverged(self, message: str) -> None:
        qvel = np.nan_to_num(self.data.qvel, nan=np.inf)
        dof = int(np.argmax(np.abs(qvel)))
        joint = self.model.joint(int(self.model.dof_jntid[dof])).name
        raise SimulationDivergedError(self.time, f"joint {joint!r}", message)

    def ft_true(self, foot: str) -> NDArray[np.float64]:
        """The exact wrench on the robot above ``foot``'s sensor, in the sensor frame [N, N·m]."""
        return self.ft_true_of(foot, self.data.sensordata)

    def ft_true_of(self, foot: str, sensordata: NDArray[np.float64]) -> NDArray[np.float64]:
        """:meth:`ft_true` of recorded ``sensordata`` rows, shape (..., nsensordata) -> (..., 6)."""
        force, torque = self._sens[foot]
        return -np.concatenate((sensordata[..., force], sensordata[..., torque]), axis=-1)

    @property
    def ft_sample_every(self) -> int:
        """Physics steps between two F-T samples [-]; the first is taken at step 0."""
        return self._ft_every

    def ft_channel(self, foot: str) -> FtChannel:
        """The sensor-effect channel of ``foot``'s F-T sensor (its state is the last sample)."""
        return self._ft[foot]

    def controls_of(self, setpoints: NDArray[np.float64]) -> NDArray[np.float64]:
        """Actuator controls (``data.ctrl`` rows) of servo setpoints [rad], shape (..., J)."""
        setpoints = np.asarray(setpoints, dtype=np.float64)
        ctrl = np.zeros((*setpoints.shape[:-1], self.model.nu))
        ctrl[..., self._act] = setpoints * np.asarray(self._gear)
        return ctrl

    def sensor_slice(self, name: str) -> slice:
        """Where MuJoCo sensor ``name`` sits in ``data.sensordata``."""
        s = self.model.sensor(name)
        adr = int(s.adr[0])
        return slice(adr, adr + int(s.dim[0]))

    def _sample_ft(self) -> None:
        if self.robot.effects.sensors:
            for foot, channel in self._ft.items():
                channel.sample(self.ft_true(foot))

    def ft(self, foot: str) -> NDArray[np.float64]:
        """The measured wrench of ``foot``'s sensor (see the module docstring) [N, N·m]."""
        if foot not in self._sens:
            raise ParameterError(f"unknown foot {foot!r}; feet: {sorted(self._sens)}")
        if self.robot.effects.sensors:
            return self._ft[foot].output.copy()
        return self.ft_true(foot)

    def encoders(self) -> NDArray[np.float64]:
        """Measured joint angles, motor side / N [rad], in joint order."""
        return self.encoders_of(self.data.qpos)

    def encoders_of(self, qpos: NDArray[np.float64]) -> NDArray[np.float64]:
        """:meth:`encoders` of recorded ``qpos`` rows, shape (..., nq) -> (..., J) [rad]."""
        return encoder_angles(qpos, self._qadr, self.robot)

    @property
    def joint_qpos_addresses(self) -> list[int]:
        """Each driven joint's address in ``qpos``, in joint order."""
        return self._qadr

    @property
    def _imu_rng(self) -> np.random.Generator:
        """The IMU's noise stream, made on its first draw (the same draws as made at start)."""
        if self._imu_rng_now is None:
            self._imu_rng_now = np.random.default_rng(self._imu_stream)
        return self._imu_rng_now

    def imu(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Gyro [rad/s], accelerometer [m/s²] and orientation quaternion (w, x, y, z)."""
        names = self.robot.imu
        gyro, accel, quat = (
            self.data.sensor(n).data.copy()
            for n in (names.gyro, names.accelerometer, names.orientation)
        )
        if self.robot.effects.sensors:
            p = self.robot.sensor_params
            rng = self._imu_rng
            gyro += p.gyro_noise_std * rng.standard_normal(3)
            accel += p.accel_noise_std * rng.standard_normal(3)
        return gyro, accel, quat


def encoder_angles(
    qpos: NDArray[np.float64], addresses: Sequence[int], robot: RobotDescription
) -> NDArray[np.float64]:
    """What ``robot``'s encoders read of ``qpos`` rows (..., nq) -> (..., J) [rad].

    The driven joints' motor-side angles at ``addresses``, quantised to the encoder
    resolution when the sensor effect is on.
    """
    q = np.asarray(qpos)[..., list(addresses)]
    if robot.effects.sensors:
        step = np.full(q.shape, robot.sensor_params.encoder_resolution)
        return quantise(q, step)
    return q.copy()
