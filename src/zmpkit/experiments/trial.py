r"""One step / push trial on a virtual robot, recorded as a real robot's experiment would be.

Timeline (simulated time): the robot starts upright in double support and stands for
``settle_s``; recording starts; after ``startup_window_s`` of quiet standing (the start-up
window, for the ZMP offset) the lean to the target begins at ``t_step``; it is held for
``hold_s`` — or, with ``max_hold_s``, until the measured ZMP has settled, and in any case
only until a creep carries it toward the edge of the feet
(:class:`~zmpkit.experiments.hold.HoldMonitor`, which reads only the recorded F-T sensors).
The lean angle :math:`\theta_{ref} = \arcsin(x_{ref} / l_{lean})` (design lean
length, :mod:`zmpkit.experiments.lean`) is not applied as a raw step, which would tip a
0.9 m, 62 kg pendulum over: it passes through the robot's servo trajectory limits (velocity
and acceleration, :class:`~zmpkit.sim.servo.TrajectoryLimiter`), scaled so no leaning joint
exceeds them, and the joint setpoints are streamed every servo tick. A push, if any, acts
from ``t_step`` for its duration.

Recorded, at the F-T sensor rate (:class:`~zmpkit.experiments.trial_record.StepTrialRecord`):
both feet's wrenches (what the sensors measure), the joint encoders, the streamed joint
setpoints (the commanded angles) and the IMU. Nothing else of the simulation is read for the
record.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Protocol, cast

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.config import PushConfig, StepExperimentConfig
from zmpkit.experiments.ft_faults import FtFaults
from zmpkit.experiments.history import previous_target, replay_previous_lean, stance_offsets
from zmpkit.experiments.hold import HoldEnd, HoldMonitor
from zmpkit.experiments.lean import Lean, design_lean_model, lean_angle
from zmpkit.experiments.trial_record import StepTrialRecord
from zmpkit.experiments.zmp_reading import ZmpReader
from zmpkit.io import feet_from_mapping
from zmpkit.robots.robot import Robot
from zmpkit.signals import PLANES
from zmpkit.sim.servo import ServoLimits, TrajectoryLimiter
from zmpkit.sim.world import Simulation

__all__ = [
    "CONTROL_PERIOD_S",
    "LeanController",
    "run_step_trial",
    "trial_seed",
]


class LeanController(Protocol):
    """What drives the lean in a controlled trial: a target in, an ankle lean angle out."""

    def set_target(self, x_ref: float) -> float:
        """Set the ZMP target [m]; returns the target in use [m]."""
        ...

    def step(self) -> float:
        """Advance one control period; the lean angle to command [rad]."""
        ...


_TABLE_POINTS = 65
CONTROL_PERIOD_S = 0.01
"""Default period at which a lean controller is stepped [s]; a robot's balance model gives its
own (:attr:`~zmpkit.robots.robot.BalanceModel.control_period_s`)."""
_MAX_REACH_FRACTION = 0.3  # lean table covers ZMPs up to this fraction of l_lean [-]


def trial_seed(seed: int, plane: str, target_m: float) -> int:
    """The noise seed of one trial, derived from the sweep's seed, plane and target [-]."""
    micro = round(target_m * 1e6) + 2**31
    return int(np.random.SeedSequence([seed, PLANES.index(plane), micro]).generate_state(1)[0])


class _LeanStream:
    """Setpoints of the leaning joints along a servo-limited lean-angle trajectory.

    The joint targets are tabulated over ``±angle_range_rad`` once; the lean angle follows
    its target through the servo's velocity and acceleration limits, scaled so no leaning
    joint exceeds them (or through the robot's own lean limits, when it gives them).
    """

    def __init__(
        self,
        lean: Lean,
        angle_range_rad: float,
        limits: ServoLimits,
        dt: float,
        lean_limits: ServoLimits | None = None,
    ) -> None:
        grid = np.linspace(-angle_range_rad, angle_range_rad, 2 * _TABLE_POINTS - 1)
        table = [lean.joint_targets(float(a)) for a in grid]
        self.joints = tuple(table[0])
        self._grid = grid
        self._values = [np.array([row[j] for row in table]) for j in self.joints]
        gain = max(abs(table[-1][j]) for j in self.joints) / angle_range_rad
        scaled = lean_limits or ServoLimits(
            limits.max_velocity / gain, limits.max_acceleration / gain
        )
        self._limiter = TrajectoryLimiter([0.0], scaled, dt)

    def set_target(self, angle_rad: float) -> None:
        """The lean angle to move to [rad], within ``±angle_range_rad``."""
        self._limiter.set_target([angle_rad])

    def tick(self) -> list[float]:
        """Advance one servo tick; the leaning joints' setpoints [rad], order of ``joints``."""
        angle = self._limiter.tick()[0]
        return [float(np.interp(angle, self._grid, v)) for v in self._values]


class _Pusher:
    """A horizontal force on the robot, applied at a body's CoM or at the whole-body CoM."""

    def __init__(
        self, sim: Simulation, push: PushConfig, plane: str, bodies: Mapping[str, str]
    ) -> None:
        self._data = sim.data
        self._body = sim.model.body(bodies[push.point]).id
        self._at_com = push.point == "com"
        self.force = np.zeros(3)
        self.force[PLANES.index(plane)] = push.force_n

    def apply(self, on: bool) -> None:
        frc = self._data.xfrc_applied[self._body]
        if not on:
            frc[:] = 0.0
            return
        frc[:3] = self.force
        if self._at_com:
            arm = self._data.subtree_com[0] - self._data.xipos[self._body]
            frc[3:] = np.cross(arm, self.force)


def _sample(sim: Simulation, stream_q: list[float]) -> list[NDArray[np.float64]]:
    gyro, accel, quat = sim.imu()
    return [
        np.array([sim.time]),
        sim.ft("right"),
        sim.ft("left"),
        sim.encoders(),
        np.array(stream_q),
        gyro,
        accel,
        quat,
    ]


def run_step_trial(
    config: StepExperimentConfig,
    target_m: float,
    controller: Callable[[], LeanController] | None = None,
    *,
    record_qpos: bool = False,
) -> StepTrialRecord:
    """Run one trial of ``config`` for the ZMP target ``target_m`` [m] and record it.

    Without ``controller`` the lean angle steps to the LIPM angle (the classic open-loop
    ankle strategy of paper A Fig. 9). With it, ``controller()`` builds a
    :class:`LeanController` (a picklable factory, so trials can run in worker processes)
    whose target is set at ``t_step`` and which is stepped every control period of the robot;
    its angle goes through the same servo limits. ``record_qpos`` also keeps the simulator's
    configuration per sample (:attr:`StepTrialRecord.qpos`, to render the trial).

    Raises:
        ParameterError: if the target is out of reach of the lean.
        SimulationDivergedError: if the simulation diverges (says when and where).
    """
    lean = design_lean_model(config.robot, config.plane)
    angle = lean_angle(target_m, lean.lean_length_m)
    seed = trial_seed(config.seed, config.plane, target_m)
    robot = config.robot
    sim = robot.make_simulation(config.effects, config.truth, seed=seed)
    balance = robot.require_balance()
    reach = lean_angle(_MAX_REACH_FRACTION * lean.lean_length_m, lean.lean_length_m)

    def make_stream() -> _LeanStream:
        return _LeanStream(lean, reach, sim.robot.servo_limits, sim.dt, balance.lean_limits)

    offsets = _carry_in(sim, config, target_m, lean, make_stream, seed)
    t_step = sim.time + round(config.t_step_s / sim.dt) * sim.dt
    reader = ZmpReader(
        sim,
        config.plane,
        feet_from_mapping(robot.feet_mounts()),
        robot.contact_force_threshold_n,
        FtFaults(config.faults) if config.faults else None,
    )
    command = _command(angle, target_m, controller, sim.dt, balance.control_period_s, reader)
    stream = make_stream() if command is not None else None
    pusher = _Pusher(sim, config.push, config.plane, balance.push_bodies) if config.push else None
    monitor = _monitor(config, target_m, t_step, robot)
    qpos: list[NDArray[np.float64]] | None = [] if record_qpos else None
    feedback = reader if command is not None and command.reads_zmp else None
    data = _record(sim, config, (stream, command, offsets), pusher, monitor, qpos, feedback)
    end = monitor.finish(float(data[-1, 0]))
    return _trial_record(config.plane, target_m, t_step, angle, lean, sim, data, end, qpos)


def _trial_record(
    plane: str,
    target_m: float,
    t_step: float,
    angle: float,
    lean: Lean,
    sim: Simulation,
    data: NDArray[np.float64],
    end: HoldEnd,
    qpos: list[NDArray[np.float64]] | None,
) -> StepTrialRecord:
    """The trial's record from its recorded rows ``data`` (time, wrenches, joints, IMU)."""
    j = len(sim.joint_names)
    return StepTrialRecord(
        plane=plane,
        target_m=target_m,
        t_step_s=t_step,
        lean_angle_rad=angle,
        lean_length_m=lean.lean_length_m,
        joint_names=tuple(sim.joint_names),
        time=data[:, 0],
        right_wrench=data[:, 1:7],
        left_wrench=data[:, 7:13],
        encoders=data[:, 13 : 13 + j],
        commanded=data[:, 13 + j : 13 + 2 * j],
        imu=data[:, 13 + 2 * j :],
        hold_end=end.kind,
        hold_note=end.note,
        qpos=None if qpos is None else np.array(qpos),
    )


def _carry_in(
    sim: Simulation,
    config: StepExperimentConfig,
    target_m: float,
    lean: Lean,
    make_stream: Callable[[], _LeanStream],
    seed: int,
) -> NDArray[np.float64]:
    """Stance offsets [rad] and the previous lean, if the truth asks (:mod:`.history`)."""
    variability = sim.robot.variability
    leaning = tuple(lean.joint_targets(0.0))
    offsets = stance_offsets(variability, sim.joint_names, leaning, seed)
    previous = previous_target(config.targets_m, target_m) if variability.sequence else None
    if previous is not None:
        replay_previous_lean(sim, lean, make_stream, previous, offsets)
    elif np.any(offsets):
        sim.servo.reset(list(np.asarray(sim.servo.position) + offsets))
    return offsets


def _monitor(
    config: StepExperimentConfig, target_m: float, t_step_s: float, robot: Robot
) -> HoldMonitor:
    """The hold monitor of one trial, from the design's sensor mounts and support polygon."""
    return HoldMonitor(
        config.plane,
        target_m,
        t_step_s,
        config.startup_window_s,
        config.hold_s,
        config.max_hold_s,
        feet_from_mapping(robot.feet_mounts()),
        robot.require_balance().support_polygon_m[config.plane],
        robot.contact_force_threshold_n,
    )


class _Command:
    """The lean-angle target per servo tick after the step (None: keep the last one).

    With a controller that reads the ZMP (``reads_zmp``), each control tick gives it the
    measured ZMP from ``reader`` (None for a missing sample).
    """

    def __init__(
        self,
        angle: float,
        controller: LeanController | None,
        every: int,
        dt: float,
        reader: ZmpReader | None,
    ) -> None:
        self._angle, self._controller, self._every, self._dt = angle, controller, every, dt
        self.reads_zmp = bool(getattr(controller, "reads_zmp", False))
        self._reader = reader if self.reads_zmp else None
        self.period_ticks = every

    def __call__(self, k: int) -> float | None:
        controller = self._controller
        if controller is None:
            return self._angle if k == 0 else None
        if k % self._every:
            return None
        if self._reader is None:
            return controller.step()
        measured = self._reader.read(k * self._dt)
        return cast(_ZmpFeedbackController, controller).step(measured)


class _ZmpFeedbackController(Protocol):
    """A lean controller that reads the measured ZMP each tick (``reads_zmp`` is true)."""

    def step(self, measured_zmp_m: float | None, /) -> float:
        """Advance one period with this tick's measured ZMP (None: missing) [rad]."""
        ...


def _command(
    angle: float,
    target_m: float,
    controller: Callable[[], LeanController] | None,
    dt: float,
    period: float = CONTROL_PERIOD_S,
    reader: ZmpReader | None = None,
) -> _Command | None:
    """Lean-angle target per servo tick after the step (None: keep), or None for no lean."""
    every = max(1, round(period / dt))
    if controller is None:
        return _Command(angle, None, every, dt, None) if angle else None
    lean_controller = controller()
    lean_controller.set_target(target_m)
    return _Command(angle, lean_controller, every, dt, reader)


def _record(
    sim: Simulation,
    config: StepExperimentConfig,
    lean: tuple[_LeanStream | None, _Command | None, NDArray[np.float64]],
    pusher: _Pusher | None,
    monitor: HoldMonitor,
    qpos: list[NDArray[np.float64]] | None = None,
    reader: ZmpReader | None = None,
) -> NDArray[np.float64]:
    """Step ``sim`` through the trial's timeline; one row per F-T sample after settling.

    ``lean`` is the lean stream, its command per tick and the stance offsets [rad]. The
    timeline starts at the simulation's current time; the trial ends when ``monitor`` says
    so, at the latest at its end time. If ``qpos`` is a list, the simulator's configuration
    of each sample is appended to it. A ``reader`` (for a controller that reads the ZMP)
    takes its start-up offset over the start-up window, once per control period.
    """
    stream, command, offsets = lean
    t0 = sim.time
    dt, names = sim.dt, list(sim.joint_names)
    every = max(1, round(1.0 / (sim.robot.sensor_params.ft_rate_hz * dt)))
    n_settle, n_step = round(config.settle_s / dt), round(config.t_step_s / dt)
    n_push_end = n_step + (round(config.push.duration_s / dt) if config.push else 0)
    index = [names.index(j) for j in stream.joints] if stream else []
    setpoints = list(sim.servo.position)
    rows: list[NDArray[np.float64]] = []
    n_startup = n_step - round(config.startup_window_s / dt)
    every_control = command.period_ticks if command is not None else 1
    for k in range(round((monitor.end_time_s - t0) / dt)):
        if reader is not None and n_startup <= k < n_step and (k - n_step) % every_control == 0:
            reader.observe_startup()
        if stream is not None and command is not None and k >= n_step:
            target = command(k - n_step)
            if target is not None:
                stream.set_target(target)
            for i, q in zip(index, stream.tick(), strict=True):
                setpoints[i] = q + float(offsets[i])
            sim.servo.reset(setpoints)
        if pusher is not None:
            pusher.apply(n_step <= k < n_push_end)
        sim.step(1)
        if (k + 1) % every == 0 and k + 1 > n_settle:
            row = np.concatenate(_sample(sim, setpoints))
            rows.append(row)
            if qpos is not None:
                qpos.append(sim.data.qpos.copy())
            if monitor.update(float(row[0]), row[1:7], row[7:13]):
                break
    return np.vstack(rows)
