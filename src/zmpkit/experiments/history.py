r"""What a virtual robot carries into a trial: the previous trial's lean and its stance.

A real robot runs a sweep's trials in sequence without a reset (paper A: "the robot does not
keep the initial value of the ZMP"), so backlash and friction leave each trial in the state
the previous lean left them in, and its stance differs a little from trial to trial. When
the robot's truth asks for it (:class:`~zmpkit.sim.sensor_errors.TrialVariability`), a trial
starts with

- its **stance**: each leaning joint's setpoint offset by a draw of
  :math:`\mathcal N(0, \sigma_{stance}^2)` [rad] (the trial's own seeded stream), for the
  whole trial;
- the **previous lean**: the lean to the previous target of the sweep (targets in increasing
  order, as a sweep runs them), held for ``previous_hold_s`` (move included), then the way
  back to upright, held as long; recording starts after that and the usual settling.

Both are off for a truth without a ``variability`` section: such a robot repeats itself
exactly.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.lean import Lean, lean_angle
from zmpkit.sim.sensor_errors import TrialVariability
from zmpkit.sim.world import Simulation

__all__ = ["previous_target", "replay_previous_lean", "stance_offsets"]

_STANCE_STREAM = 7  # the stance draw's stream, apart from the sensors' [-]


class _Stream(Protocol):
    """What :func:`replay_previous_lean` needs of a lean stream (joints, target, tick)."""

    joints: tuple[str, ...]

    def set_target(self, angle_rad: float) -> None:
        """The lean angle to move to [rad]."""
        ...

    def tick(self) -> list[float]:
        """Advance one servo tick; the leaning joints' setpoints [rad]."""
        ...


def previous_target(targets: Sequence[float], target_m: float) -> float | None:
    """The target run before ``target_m`` [m] in a sweep (increasing order); None if first."""
    ordered = sorted(targets)
    k = ordered.index(target_m)
    return ordered[k - 1] if k > 0 else None


def stance_offsets(
    variability: TrialVariability, joints: Sequence[str], leaning: Sequence[str], seed: int
) -> NDArray[np.float64]:
    """Setpoint offset of each driven joint [rad]: a draw for the leaning ones, else 0."""
    offsets = np.zeros(len(joints))
    if variability.stance_std_rad > 0.0:
        rng = np.random.default_rng([seed, _STANCE_STREAM])
        for name in leaning:
            offsets[list(joints).index(name)] = variability.stance_std_rad * rng.standard_normal()
    return offsets


def replay_previous_lean(
    sim: Simulation,
    lean: Lean,
    make_stream: Callable[[], _Stream],
    previous_m: float,
    offsets: NDArray[np.float64],
) -> None:
    """Lean ``sim`` to ``previous_m`` [m], hold, and come back upright (module docstring)."""
    hold_s = sim.robot.variability.previous_hold_s
    stream = make_stream()
    names = list(sim.joint_names)
    index = [names.index(j) for j in stream.joints]
    setpoints = list(np.asarray(sim.servo.position) + offsets)
    for angle in (lean_angle(previous_m, lean.lean_length_m), 0.0):
        stream.set_target(angle)
        for _ in range(round(hold_s / sim.dt)):
            for i, q in zip(index, stream.tick(), strict=True):
                setpoints[i] = q + float(offsets[i])
            sim.servo.reset(setpoints)
            sim.step(1)
