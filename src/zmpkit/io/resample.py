"""Putting the streams of a log onto one clock by linear interpolation.

Rules, the same for every stream:

- **No extrapolation.** With ``rate_hz`` the new clock spans only the interval that every
  stream covers (the latest first sample to the earliest last sample). With explicit ``time``,
  a time outside any stream's span is an error that names the stream and its span.
- **Gaps.** A target time that falls inside a gap between two consecutive source samples
  longer than ``max_gap_s`` is an error naming the stream and the gap: interpolating across
  it would invent data. The default ``max_gap_s`` is :data:`DEFAULT_MAX_GAP_PERIODS` times
  the median sample period of that stream; pass ``math.inf`` to interpolate across anything.
- **Values.** ``(1 − w) a + w b`` between neighbours, so target times that coincide with
  source samples give those samples exactly. Quaternions are interpolated the same way after
  aligning consecutive signs (q and −q are one rotation), then renormalised (nlerp).
"""

from __future__ import annotations

import dataclasses
from typing import overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit._validate import finite_array, positive
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.io.ft_log import FtLog
from zmpkit.io.robot_log import ImuLog, JointLog, RobotLog

__all__ = ["DEFAULT_MAX_GAP_PERIODS", "interpolate_stream", "merge_feet", "resample"]

DEFAULT_MAX_GAP_PERIODS = 10.0
"""Default longest gap interpolated across, in median sample periods of the stream [-]."""


@overload
def resample(
    log: RobotLog,
    *,
    rate_hz: float | None = None,
    time: ArrayLike | None = None,
    max_gap_s: float | None = None,
) -> RobotLog: ...


@overload
def resample(
    log: FtLog,
    *,
    rate_hz: float | None = None,
    time: ArrayLike | None = None,
    max_gap_s: float | None = None,
) -> FtLog: ...


def resample(
    log: RobotLog | FtLog,
    *,
    rate_hz: float | None = None,
    time: ArrayLike | None = None,
    max_gap_s: float | None = None,
) -> RobotLog | FtLog:
    """Put every stream of ``log`` onto one clock.

    Args:
        log: a :class:`~zmpkit.io.robot_log.RobotLog` or an :class:`~zmpkit.io.ft_log.FtLog`.
        rate_hz: a uniform clock at this rate [Hz] over the span all streams cover.
        time: explicit target times [s], strictly increasing; give this or ``rate_hz``.
        max_gap_s: longest source gap to interpolate across [s]; None for the default rule.

    Returns:
        A log of the same type whose streams all share the new sample times.

    Raises:
        ParameterError: neither or both of ``rate_hz`` and ``time``; a target time outside a
            stream's span.
        InputFileError: the streams do not overlap, or a target time falls in a long gap.
    """
    robot = log if isinstance(log, RobotLog) else RobotLog(ft=log, source=log.source)
    target = _target_time(robot, rate_hz, time)
    ft = _resample_ft(robot.ft, target, max_gap_s)
    if isinstance(log, FtLog):
        return ft
    joints = None if robot.joints is None else _resample_joints(robot.joints, target, max_gap_s)
    imu = None if robot.imu is None else _resample_imu(robot.imu, target, max_gap_s)
    return dataclasses.replace(robot, ft=ft, joints=joints, imu=imu)


def merge_feet(
    right_time: NDArray[np.float64],
    right_wrench: NDArray[np.float64],
    left_time: NDArray[np.float64],
    left_wrench: NDArray[np.float64],
    source: str,
    max_gap_s: float | None = None,
) -> FtLog:
    """Join two feet recorded on separate clocks into one :class:`FtLog`.

    Identical clocks are joined as they are. Otherwise the right foot's clock is kept, cut to
    the span both feet cover, and the left wrench is interpolated onto it (module rules).

    Raises:
        InputFileError: the two feet's spans do not overlap, or a long gap is crossed.
    """
    if np.array_equal(right_time, left_time):
        return FtLog(right_time, right_wrench, left_wrench, source=source)
    spans = {"right foot": right_time, "left foot": left_time}
    start, end = _common_span(spans, source)
    keep = (right_time >= start) & (right_time <= end)
    target = right_time[keep]
    left = interpolate_stream(left_time, left_wrench, target, "left foot", source, max_gap_s)
    return FtLog(target, right_wrench[keep], left, source=source)


def interpolate_stream(
    time: NDArray[np.float64],
    values: NDArray[np.float64],
    target: NDArray[np.float64],
    name: str,
    source: str,
    max_gap_s: float | None = None,
) -> NDArray[np.float64]:
    """Linearly interpolate ``values`` (N, K) sampled at ``time`` (N,) onto ``target`` (M,).

    Raises:
        ParameterError: a target time outside ``[time[0], time[-1]]``.
        InputFileError: a target time inside a gap longer than ``max_gap_s`` (module rules).
    """
    if target.size and (target[0] < time[0] or target[-1] > time[-1]):
        raise ParameterError(
            f"{name} covers t = {time[0]:g} … {time[-1]:g} s; target times "
            f"{target[0]:g} … {target[-1]:g} s would need extrapolation, which is not done"
        )
    if time.size == 1:
        return np.repeat(values[:1], target.size, axis=0)
    i = np.clip(np.searchsorted(time, target, side="right") - 1, 0, time.size - 2)
    _check_gaps(time, target, i, name, source, max_gap_s)
    w = ((target - time[i]) / (time[i + 1] - time[i]))[:, None]
    return (1.0 - w) * values[i] + w * values[i + 1]


def _check_gaps(
    time: NDArray[np.float64],
    target: NDArray[np.float64],
    i: NDArray[np.intp],
    name: str,
    source: str,
    max_gap_s: float | None,
) -> None:
    steps = np.diff(time)
    limit = DEFAULT_MAX_GAP_PERIODS * float(np.median(steps)) if max_gap_s is None else max_gap_s
    inside = (target > time[i]) & (target < time[i + 1])
    bad = np.flatnonzero(inside & (steps[i] > limit))
    if bad.size:
        k = int(i[bad[0]])
        raise InputFileError(
            source,
            f"{name} has a gap of {steps[k]:g} s (t = {time[k]:g} … {time[k + 1]:g} s), longer "
            f"than max_gap_s = {limit:g} s; interpolating across it would invent data — cut "
            "the log or pass a larger max_gap_s",
        )


def _target_time(
    log: RobotLog, rate_hz: float | None, time: ArrayLike | None
) -> NDArray[np.float64]:
    if (rate_hz is None) == (time is None):
        raise ParameterError("give exactly one of rate_hz [Hz] and time [s]")
    if time is not None:
        target = finite_array("time", time, (None,))
        if target.size == 0 or np.any(np.diff(target) <= 0.0):
            raise ParameterError("time must be a non-empty, strictly increasing array [s]")
        return target
    assert rate_hz is not None  # exactly one of the two is given, and time is not
    rate = positive("rate_hz", rate_hz, "Hz")
    start, end = _common_span(log.streams(), log.source)
    n = int(np.floor((end - start) * rate + 1e-9)) + 1
    # the 1e-9 slack keeps a last tick that lands on `end` up to rounding; clip it onto `end`
    return np.minimum(start + np.arange(n) / rate, end)


def _common_span(spans: dict[str, NDArray[np.float64]], source: str) -> tuple[float, float]:
    start = max(float(t[0]) for t in spans.values())
    end = min(float(t[-1]) for t in spans.values())
    if start > end:
        covers = "; ".join(f"{k} covers t = {t[0]:g} … {t[-1]:g} s" for k, t in spans.items())
        raise InputFileError(source, f"the streams do not overlap in time: {covers}")
    return start, end


def _resample_ft(ft: FtLog, target: NDArray[np.float64], gap: float | None) -> FtLog:
    both = np.hstack([ft.right_wrench, ft.left_wrench])
    values = interpolate_stream(ft.time, both, target, "ft", ft.source, gap)
    return FtLog(target, values[:, :6], values[:, 6:], source=ft.source)


def _resample_joints(joints: JointLog, target: NDArray[np.float64], gap: float | None) -> JointLog:
    def interp(values: NDArray[np.float64]) -> NDArray[np.float64]:
        return interpolate_stream(joints.time, values, target, "joints", joints.source, gap)

    velocity = None if joints.velocity is None else interp(joints.velocity)
    return JointLog(target, joints.names, interp(joints.position), velocity, joints.source)


def _resample_imu(imu: ImuLog, target: NDArray[np.float64], gap: float | None) -> ImuLog:
    def interp(values: NDArray[np.float64]) -> NDArray[np.float64]:
        return interpolate_stream(imu.time, values, target, "imu", imu.source, gap)

    orientation = None
    if imu.orientation_xyzw is not None:
        q = interp(_align_signs(imu.orientation_xyzw))
        orientation = q / np.linalg.norm(q, axis=1, keepdims=True)
    return ImuLog(
        target,
        interp(imu.angular_velocity),
        interp(imu.linear_acceleration),
        orientation,
        imu.source,
    )


def _align_signs(q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Flip quaternions so that consecutive ones have a non-negative dot product."""
    flips = np.sum(q[1:] * q[:-1], axis=1) < 0.0
    signs = np.concatenate([[1.0], np.where(np.cumsum(flips) % 2 == 1, -1.0, 1.0)])
    return q * signs[:, None]
