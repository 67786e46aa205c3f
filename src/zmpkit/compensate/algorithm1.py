r"""Paper B's Algorithm 1: compensate the single-CoM (3D-LIPM) abstraction offline (Fig. 5).

The pattern generator believes the 3D-LIPM, so its CoM realises the desired ZMP ``p_r`` only
for a point mass. The whole robot (legs swinging, trunk and thighs with their own inertia)
produces the multibody ZMP ``p`` instead. Algorithm 1 iterates, for ``i = 1..n``:

.. math::

    q = \text{pattern}(p_r + p_o), \quad p = \text{ZMP}_{multibody}(q), \quad
    p_o \leftarrow p_o + (p_r - p),

with ``p_o = 0`` first, and applies ``p' = p_r + p_o`` as the new reference. ``pattern`` is the
preview-control CoM plus the whole-body IK on the design model; the multibody ZMP is
:class:`~zmpkit.walking.multibody_zmp.InverseDynamicsZmp`. The RMS of ``p_r - p`` over both
axes and all samples is recorded at each iteration, before the update (the first value is the
error of the uncompensated pattern).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.walking import PatternConfig, generate_pattern
from zmpkit.walking.ik import IkSettings, JointTrajectory, solve_walking_ik
from zmpkit.walking.multibody_zmp import InverseDynamicsZmp
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["DEFAULT_ITERATIONS", "Algorithm1Result", "compensate_abstraction", "zmp_rms"]

DEFAULT_ITERATIONS = 10
"""Iterations of Algorithm 1 (the issue's budget) [-]."""


@dataclass(frozen=True)
class Algorithm1Result:
    """The outcome of Algorithm 1.

    Attributes:
        zmp_offset_in_world: the final p_o [m], shape (N, 2): pass it as ``zmp_offset``.
        iteration_rms_m: RMS of p_r - p at each iteration [m], shape (n,).
        desired_zmp_in_world: p_r, the linear reference [m], shape (N, 2).
        multibody_zmp_in_world: p of each iteration [m], shape (n, N, 2).
        pattern: the compensated pattern (reference p_r + p_o).
        trajectory: its IK joint trajectory.
    """

    zmp_offset_in_world: NDArray[np.float64]
    iteration_rms_m: NDArray[np.float64]
    desired_zmp_in_world: NDArray[np.float64]
    multibody_zmp_in_world: NDArray[np.float64]
    pattern: WalkingPattern
    trajectory: JointTrajectory

    @property
    def reduction_pct(self) -> float:
        """How far the last iteration's RMS lies below the first one's [%]."""
        return float(100.0 * (1.0 - self.iteration_rms_m[-1] / self.iteration_rms_m[0]))


def zmp_rms(desired: NDArray[np.float64], actual: NDArray[np.float64]) -> float:
    """RMS of ``desired - actual`` over all samples and both axes [m], NaNs skipped."""
    error = np.asarray(desired) - np.asarray(actual)
    return float(np.sqrt(np.nanmean(error**2)))


def compensate_abstraction(
    config: PatternConfig,
    model: mujoco.MjModel,
    iterations: int = DEFAULT_ITERATIONS,
    *,
    ik_settings: IkSettings,
) -> Algorithm1Result:
    """Run Algorithm 1 on the walk ``config`` with the design model ``model``.

    Args:
        config: the walk (its linear reference is p_r).
        model: the robot's rigid model, free joint first (the IK model).
        iterations: n >= 1.
        ik_settings: settings of the IK (the robot's
            :attr:`~zmpkit.robots.robot.Robot.ik_settings`).

    Returns:
        The offset, the RMS per iteration and the last compensated pattern.
    """
    if isinstance(iterations, bool) or not isinstance(iterations, int) or iterations < 1:
        raise ParameterError(f"iterations must be an integer >= 1; got {iterations!r}")
    zmp = InverseDynamicsZmp(model)
    pattern = generate_pattern(config)
    desired = pattern.linear_zmp_reference.zmp_in_world
    offset = np.zeros_like(desired)
    rms, history = [], []
    for _ in range(iterations):
        pattern = generate_pattern(config, offset, gains=pattern.gains)
        trajectory = solve_walking_ik(pattern, model, ik_settings)
        actual = zmp.from_trajectory(trajectory).zmp_in_world
        rms.append(zmp_rms(desired, actual))
        history.append(actual)
        offset = offset + np.nan_to_num(desired - actual)
    return Algorithm1Result(
        offset - np.nan_to_num(desired - actual),
        np.array(rms),
        desired,
        np.array(history),
        pattern,
        trajectory,
    )
