r"""A walk log cut into windows, each started from the measured state (multiple shooting).

A walk of a controller zmpkit does not have cannot be re-simulated in closed loop, and its
recorded joint commands replayed open loop over a whole walk diverge from the recording
within a step or two (the commanded feedback answered the robot's motion, not the
candidate's). So the log (:mod:`zmpkit.experiments.walk_log`) is cut into windows of
``window_s``; each window is replayed open loop from its recorded commands, starting from
the state the sensors measured at its start (:class:`WindowStart`), and its first
``burn_in_s`` is not scored while the unmeasured states settle (:mod:`~zmpkit.simfit.shooting`).
Consecutive windows overlap by the burn-in, so their scored parts tile the log.

**The measured start state** at the window's first row :math:`t_0`:

- joint angles: the encoders at :math:`t_0` [rad];
- joint speeds: the least-squares slope of the encoders over the
  :math:`2k+1 =` :data:`SLOPE_ROWS` rows centred on :math:`t_0` (a first-order
  Savitzky–Golay differentiator, :math:`\dot q = \sum_i (t_i - \bar t)(q_i - \bar q) /
  \sum_i (t_i - \bar t)^2`): an encoder quantum :math:`\delta` and row period :math:`T` give
  a speed error of about :math:`\delta / (T \sqrt{12 \sum_i i^2})` (0.014 rad/s for the
  built-in walker's 0.0015 rad at 100 Hz over 5 rows), and the centred fit has no lag;
- base orientation and angular velocity: the IMU quaternion and gyro at :math:`t_0`
  (without a gyro, the orientation's central difference);
- base position and linear velocity: from the kinematics of the stance foot — the one with
  the larger F-T :math:`F_z` — its sole centre on the floor and at rest
  (:meth:`~zmpkit.simfit.log_kinematics.LogKinematics.place_base`);
- the drives' integral terms: summed from the log, the integral of the commanded angle
  minus the encoder from the log's first row (where it is taken to be zero, as a robot's
  drives start a walk) by the trapezoid rule, clamped as the candidate's drive clamps it
  (:mod:`~zmpkit.simfit.shooting`): the built-in walker's integral gain is a hundredth of its
  proportional one per second, so its integral remembers the whole walk and no burn-in
  would settle it;
- the gear deflections and link flex, which no sensor sees: replayed on the candidate's own
  springs under the load the F-T sensors measured over the :data:`LOAD_HISTORY_S` before
  the start (:class:`LoadHistory`, :mod:`~zmpkit.simfit.loaded_start`; started at zero,
  their release rang through the window and pulled the fit towards stiff candidates);
- what else no sensor sees — the winding current, the compliance's speeds — starts at
  zero. The burn-in lets it settle (the drive's time constants are milliseconds, the F-T
  filter's 8 ms; :data:`DEFAULT_WINDOW_S` says how long was needed).

**Windows where the robot stood** are dropped: each window's cost is normalised by its own
recorded variation (:mod:`~zmpkit.simfit.cost`: tracking error, ZMP about its trend, trunk
tilt spectrum), which while standing is the sensors' noise, so its cost would weigh noise,
not the model. A window is kept when each of the three is at least :data:`STANDING_SHARE`
of its median over the log's windows.

**The noise floor** (:mod:`~zmpkit.simfit.adequacy`) compares the fitted model's rollout
with replicas of the experiment recorded by the fitted model itself. Replica ``k`` of a
window starts :data:`REPLICA_LEADS` ``[k]`` burn-ins earlier, from the state measured there
(:attr:`ShootingWindow.replicas`), so at the window's start it carries developed unmeasured
states and a replay's drift, as the robot did, while the fit's rollout starts from the
measured state: the floor holds the shooting's start-state error, and the replicas' spread
(different leads, different start errors) the noise-only intervals'
(:mod:`~zmpkit.simfit.noise_intervals`), not only the sensors' noise. These replicas are
not themselves cut from a log their own sensors measured, so they miss what that start-state
estimation does to the estimate; for the intervals a log ``zmpkit walk`` wrote is walked
again and re-cut (:mod:`~zmpkit.simfit.pipeline_replicas`), and any other log's windows are
replayed again and re-cut from the replica's own sensors
(:mod:`~zmpkit.simfit.window_replicas`). A log's first window
has no earlier state and is its own replica (its floor holds the sensors' noise only).

**A walk that fell** (IMU pitch or roll past
:data:`~zmpkit.experiments.walk_trial.FALL_TILT_RAD`, the rule of ``zmpkit walk``) is cut
:data:`~zmpkit.simfit.walk_plan.FALL_MARGIN_S` before the fall; later windows are dropped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TypeVar, cast

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.walk_log import WalkLog
from zmpkit.experiments.walk_trial import FALL_TILT_RAD
from zmpkit.robots.robot import Robot
from zmpkit.sensors.imu import quaternion_pitch_roll
from zmpkit.simfit.cost import spectrum_in_band
from zmpkit.simfit.log_kinematics import FEET, LogKinematics
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.walk_plan import FALL_MARGIN_S

__all__ = [
    "DEFAULT_BURN_IN_S",
    "DEFAULT_WINDOW_S",
    "LOAD_HISTORY_S",
    "REPLICA_LEADS",
    "SLOPE_ROWS",
    "STANDING_SHARE",
    "LoadHistory",
    "ShootingWindow",
    "WindowStart",
    "check_window",
    "cut_window",
    "log_fall_time",
    "log_windows",
    "replica_experiment",
]

DEFAULT_WINDOW_S = 1.2
"""Window length [s]: a burn-in and 0.9 s scored, about two steps of a small humanoid's walk,
so each window holds both single supports (the ZMP term sees the F-T move between the feet)
and resolves the trunk spectrum to 1.1 Hz. Measured on a 10 s ``zmpip`` walk of the built-in
walker (M, G, S; hidden PID scale 0.797, gear stiffness 1424 N·m/rad), the mean window cost
of the true parameters and whether it is lower than with the PID scale at ±5 % and the stiffness at
±10 %: 0.6 s windows (0.1 s burn-in) 0.059, the minimum at -5 % and -10 %; 1.0 s (0.2 s)
0.013 and 1.2 s (0.3 s) 0.0076, the minimum at the truth; 1.5 s (0.3 s) 0.0063. With a
0.2 s burn-in an earlier version's fit still found the stiffness 10 % low (the zero start
of the unmeasured states leaking into the scored rows). Longer windows fit fewer of them in
a walk and let a real robot's replay drift further."""
DEFAULT_BURN_IN_S = 0.3
"""Unscored start of each window [s] (module docstring)."""
SLOPE_ROWS = 5
"""Rows of the centred least-squares slope that gives the joint speeds [-]."""
LOAD_HISTORY_S = 0.5
"""How long before a window's start the measured load is replayed on the compliance [s]
(:func:`~zmpkit.simfit.loaded_start.replay_compliance`): a gear inside its dead band is where
the load's last swings left it. In a first study on a simulated G1's own gears (its true
state and load), 0.2 s of history cut the 90th percentile of the unloaded gears' start error
from 2.1 to 1.45 mrad and 0.5 s to 1.2 mrad; :mod:`~zmpkit.simfit.loaded_start` has the
figures of the built method from logs."""
STANDING_SHARE = 0.25
"""A window whose recorded variation is below this share of the log's median is dropped
(module docstring) [-]."""
REPLICA_LEADS = (1.0, 1.25, 1.5, 1.75)
"""How many burn-ins before its window each replica starts (module docstring) [-]."""
_MIN_SCORED_ROWS = 16
T = TypeVar("T")


@dataclass(frozen=True, eq=False)
class LoadHistory:
    """What the sensors measured on the rows before a window's start, oldest first.

    The rows within :data:`LOAD_HISTORY_S` before the start row (that row not included); none
    for a start at the log's first row.

    Attributes:
        time_s: the rows' times [s], shape (H,).
        q_rad: encoder angles of the driven joints [rad], shape (H, J).
        dq_rad_s: their speeds (module docstring) [rad/s], shape (H, J).
        imu_quat_wxyz: IMU orientation [-], shape (H, 4).
        gyro_rps: IMU angular velocity, IMU frame [rad/s], shape (H, 3).
        stance: the loaded foot of each row, an index of
            :data:`~zmpkit.simfit.log_kinematics.FEET`, shape (H,).
        wrenches: the feet's F-T readings, in :data:`FEET` order [N, N·m], shape (H, 2, 6).
    """

    time_s: NDArray[np.float64]
    q_rad: NDArray[np.float64]
    dq_rad_s: NDArray[np.float64]
    imu_quat_wxyz: NDArray[np.float64]
    gyro_rps: NDArray[np.float64]
    stance: NDArray[np.int64]
    wrenches: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class WindowStart:
    r"""What the sensors measured at a window's first row.

    Attributes:
        q_rad: encoder angles of the driven joints [rad], shape (J,).
        dq_rad_s: their speeds (module docstring) [rad/s], shape (J,).
        imu_quat_wxyz: IMU orientation [-], shape (4,).
        gyro_rps: IMU angular velocity, IMU frame [rad/s], shape (3,).
        stance: the loaded foot, an index of :data:`~zmpkit.simfit.log_kinematics.FEET`.
        error_steps_rad_s: the tracking error's integral over each row from the log's
            start, :math:`\tfrac12 (e_{i-1} + e_i)(t_i - t_{i-1})` with
            :math:`e = q_{cmd} - q_{enc}` at the joint [rad·s], shape (rows, J): what the
            drives' integral terms summed (module docstring).
        wrenches: the feet's F-T readings, in :data:`FEET` order [N, N·m], shape (2, 6):
            the load the unmeasured compliance carried (:mod:`~zmpkit.simfit.loaded_start`).
        history: the rows before, whose load is replayed on the compliance.
    """

    q_rad: NDArray[np.float64]
    dq_rad_s: NDArray[np.float64]
    imu_quat_wxyz: NDArray[np.float64]
    gyro_rps: NDArray[np.float64]
    stance: int
    error_steps_rad_s: NDArray[np.float64]
    wrenches: NDArray[np.float64]
    history: LoadHistory | None = None


@dataclass(frozen=True, eq=False)
class ShootingWindow:
    """One window of a walk log, replayed open loop from its measured start.

    Attributes:
        name: the log's name and the window's scored span.
        robot: the robot that walked.
        signals: the scored rows: commands and encoders of every driven joint, the ZMP in
            the floor frame at the feet's midpoint (:mod:`~zmpkit.simfit.log_kinematics`) [m] and
            the IMU pitch [rad].
        start: the measured state at ``command_time_s[0]``.
        command_time_s: times of the window's rows, burn-in included [s], shape (M,).
        q_cmd_rad: the recorded commands of those rows [rad], shape (M, J).
        burn_in_s: the unscored start [s].
        log_name: the log the window comes from.
        replicas: the same scored rows replayed from the states measured
            :data:`REPLICA_LEADS` burn-ins earlier (module docstring), for the noise floor;
            none for a log's first window.
        source: the file of the log (``""`` when not read from a file).
        window_s: the window length the log was cut with [s].
    """

    name: str
    robot: Robot
    signals: RecordedSignals
    start: WindowStart
    command_time_s: NDArray[np.float64]
    q_cmd_rad: NDArray[np.float64]
    burn_in_s: float
    log_name: str = ""
    replicas: tuple[ShootingWindow, ...] = ()
    source: str = ""
    window_s: float = DEFAULT_WINDOW_S


def check_window(window_s: float, burn_in_s: float) -> None:
    """Raise :class:`~zmpkit.errors.ParameterError` unless 0 <= burn-in < window < inf [s]."""
    if not (0.0 <= burn_in_s < window_s < math.inf):
        raise ParameterError(
            f"the window (--window {window_s:g} s) must be finite and longer than its "
            f"burn-in (--burn-in {burn_in_s:g} s, at least 0)"
        )


def log_fall_time(log: WalkLog) -> float | None:
    """When the IMU's pitch or roll first passed the fall tilt [s], or None."""
    for t, quat in zip(log.time_s, log.imu_quat_wxyz, strict=True):
        if max(abs(a) for a in quaternion_pitch_roll(quat)) > FALL_TILT_RAD:
            return float(t)
    return None


def _slope(time_s: NDArray[np.float64], q: NDArray[np.float64], row: int) -> NDArray:
    half = SLOPE_ROWS // 2
    lo, hi = max(0, row - half), min(len(time_s), row + half + 1)
    t = time_s[lo:hi] - time_s[lo:hi].mean()
    return np.asarray((t @ (q[lo:hi] - q[lo:hi].mean(axis=0))) / (t @ t))


def _gyro(log: WalkLog, row: int) -> NDArray[np.float64]:
    """The gyro, or the orientation's central difference in the IMU frame [rad/s]."""
    if log.gyro_rps is not None:
        return np.asarray(log.gyro_rps[row], dtype=np.float64)
    lo, hi = max(0, row - 1), min(log.time_s.size - 1, row + 1)
    q0, q1 = log.imu_quat_wxyz[lo], log.imu_quat_wxyz[hi]
    # q1 = q0 ⊗ exp(ω dt / 2): ω ≈ 2 vec(q0* ⊗ q1) / dt in the body frame
    w0, v0 = q0[0], -q0[1:]
    w1, v1 = q1[0], q1[1:]
    vec = w0 * v1 + w1 * v0 + np.cross(v0, v1)
    return np.asarray(2.0 * vec / (log.time_s[hi] - log.time_s[lo]))


def _recorded(
    log: WalkLog, rows: slice, kinematics: LogKinematics, tilt: NDArray
) -> RecordedSignals:
    wrenches = np.stack([log.right_wrench[rows], log.left_wrench[rows]], axis=1)
    readings = [
        kinematics.readings(q, quat, w)
        for q, quat, w in zip(log.q_enc_rad[rows], log.imu_quat_wxyz[rows], wrenches, strict=True)
    ]
    zmp = np.array([r[0] for r in readings]).reshape(-1, 2)
    force = np.array([r[1] for r in readings]).reshape(-1, 2)
    return RecordedSignals(
        log.time_s[rows],
        log.joint_names,
        log.q_cmd_rad[rows],
        log.q_enc_rad[rows],
        zmp,
        tilt,
        force,
    )


def log_windows(
    log: WalkLog,
    robot: Robot,
    name: str,
    window_s: float = DEFAULT_WINDOW_S,
    burn_in_s: float = DEFAULT_BURN_IN_S,
) -> list[ShootingWindow]:
    """Cut ``log`` into windows (module docstring), up to shortly before a fall.

    Raises:
        ParameterError: on a window not longer than its burn-in.
        InputFileError: on a log whose joints are not the robot's driven joints, or too
            short (or falling too soon) for one window.
    """
    check_window(window_s, burn_in_s)
    description = robot.description("none")
    if set(log.joint_names) != set(description.driven_joints):
        raise InputFileError(
            log.source or name,
            f"the log's joints {list(log.joint_names)} are not {robot.title}'s driven "
            f"joints {list(description.driven_joints)}",
        )
    order = [log.joint_names.index(j) for j in description.driven_joints]
    log = _reordered(log, order, description.driven_joints)
    kinematics = LogKinematics(robot.make_simulation("none").model, description)
    fall = log_fall_time(log)
    end = log.time_s[-1] if fall is None else fall - FALL_MARGIN_S
    tilt = np.array([quaternion_pitch_roll(q)[0] for q in log.imu_quat_wxyz])
    windows = []
    a = float(log.time_s[min(SLOPE_ROWS // 2, log.time_s.size - 1)])
    while a + window_s <= end + 1e-9:
        window = cut_window(log, robot, name, kinematics, a, window_s, burn_in_s, tilt)
        if window is not None:
            windows.append(window)
        a += window_s - burn_in_s
    windows = _moving(windows)
    if not windows:
        fell = "" if fall is None else f" (it fell at {fall:.2f} s)"
        raise InputFileError(
            log.source or name,
            f"no window of {window_s:g} s fits in the log's {end - log.time_s[0]:.2f} s{fell}; "
            "give a shorter --window or a longer log",
        )
    return windows


def _reordered(log: WalkLog, order: list[int], joints: tuple[str, ...]) -> WalkLog:
    return WalkLog(
        log.time_s, joints, log.q_cmd_rad[:, order], log.q_enc_rad[:, order],
        log.imu_quat_wxyz, log.gyro_rps, log.right_wrench, log.left_wrench,
        log.accel_mps2, log.source,
    )  # fmt: skip


def _started(log: WalkLog, a: float, threshold_n: float) -> tuple[int, WindowStart] | None:
    """The row at ``a`` [s] and the state measured there; None without a foot in contact."""
    first = int(np.searchsorted(log.time_s, a - 1e-9))
    fz = np.array([log.wrench(f)[first, 2] for f in FEET])
    if fz.max() < threshold_n:
        return None
    error = log.q_cmd_rad[: first + 1] - log.q_enc_rad[: first + 1]
    steps = 0.5 * (error[1:] + error[:-1]) * np.diff(log.time_s[: first + 1])[:, None]
    return first, WindowStart(
        log.q_enc_rad[first].copy(),
        _slope(log.time_s, log.q_enc_rad, first),
        log.imu_quat_wxyz[first].copy(),
        _gyro(log, first),
        int(np.argmax(fz)),
        steps,
        np.stack([log.wrench(f)[first] for f in FEET]),
        _history(log, first),
    )


def _history(log: WalkLog, first: int) -> LoadHistory | None:
    """The rows within :data:`LOAD_HISTORY_S` before row ``first``; None if there are none."""
    oldest = int(np.searchsorted(log.time_s, log.time_s[first] - LOAD_HISTORY_S - 1e-9))
    rows = range(oldest, first)
    if not rows:
        return None
    wrenches = np.stack([log.wrench(f)[oldest:first] for f in FEET], axis=1)
    return LoadHistory(
        log.time_s[oldest:first].copy(),
        log.q_enc_rad[oldest:first].copy(),
        np.array([_slope(log.time_s, log.q_enc_rad, r) for r in rows]),
        log.imu_quat_wxyz[oldest:first].copy(),
        np.array([_gyro(log, r) for r in rows]),
        np.argmax(wrenches[:, :, 2], axis=1).astype(np.int64),
        wrenches,
    )


def cut_window(
    log: WalkLog,
    robot: Robot,
    name: str,
    kinematics: LogKinematics,
    a: float,
    window_s: float,
    burn_in_s: float,
    tilt: NDArray[np.float64] | None = None,
) -> ShootingWindow | None:
    """The window of ``log`` starting at its row at ``a`` [s], and its replicas.

    ``log``'s joints in ``robot``'s driven-joint order; ``tilt``: its IMU pitch per row
    [rad] (None: computed). None without a foot in contact at ``a``, or with too few
    scored rows (module docstring).
    """
    if tilt is None:
        tilt = np.array([quaternion_pitch_roll(q)[0] for q in log.imu_quat_wxyz])
    time, threshold = log.time_s, kinematics.contact_threshold_n
    scored = int(np.searchsorted(time, a + burn_in_s - 1e-9))
    last = int(np.searchsorted(time, a + window_s + 1e-9))
    started = _started(log, a, threshold)
    if last - scored < _MIN_SCORED_ROWS or started is None:
        return None
    first, start = started
    rows = slice(scored, last)
    label = f"{name}@{time[scored]:.2f}-{time[last - 1]:.2f}s"
    signals = _recorded(log, rows, kinematics, tilt[rows])
    window = ShootingWindow(
        label, robot, signals, start, time[first:last].copy(), log.q_cmd_rad[first:last].copy(),
        burn_in_s, name,
    )  # fmt: skip
    replicas = []
    for lead in REPLICA_LEADS:
        started = _started(log, a - lead * burn_in_s, threshold)
        if started is None or started[0] >= first:
            continue
        row, state = started
        replicas.append(
            replace(
                window,
                start=state,
                command_time_s=time[row:last].copy(),
                q_cmd_rad=log.q_cmd_rad[row:last].copy(),
                burn_in_s=float(time[scored] - time[row]),
            )
        )
    return replace(window, replicas=tuple(replicas), source=log.source, window_s=window_s)


def replica_experiment(experiment: T, k: int) -> T:
    """What replica ``k`` of ``experiment`` replays.

    A window's ``k``-th of its :attr:`ShootingWindow.replicas` (cyclically); any other
    experiment is its own.
    """
    if isinstance(experiment, ShootingWindow) and experiment.replicas:
        return cast(T, experiment.replicas[k % len(experiment.replicas)])
    return experiment


def _variation(signals: RecordedSignals) -> NDArray[np.float64]:
    """Tracking error RMS [rad], ZMP spread about its trend [m], tilt spectrum norm [rad]."""
    track = float(np.sqrt(np.mean(np.square(signals.q_meas_rad - signals.q_cmd_rad))))
    t, zmp = signals.time_s, signals.zmp_m
    ok = np.all(np.isfinite(zmp), axis=1)
    spread = 0.0
    if np.count_nonzero(ok) >= 3:
        fit = [zmp[ok, k] - np.polyval(np.polyfit(t[ok], zmp[ok, k], 1), t[ok]) for k in (0, 1)]
        spread = float(np.sqrt(np.mean(np.square(fit[0]) + np.square(fit[1]))))
    spectrum = float(np.linalg.norm(spectrum_in_band(signals.trunk_tilt_rad, signals.dt_s)[1]))
    return np.array([track, spread, spectrum])


def _moving(windows: list[ShootingWindow]) -> list[ShootingWindow]:
    """The windows where the robot did not stand (module docstring)."""
    if not windows:
        return windows
    variation = np.array([_variation(w.signals) for w in windows])
    floor = STANDING_SHARE * np.median(variation, axis=0)
    return [w for w, v in zip(windows, variation, strict=True) if np.all(v >= floor)]
