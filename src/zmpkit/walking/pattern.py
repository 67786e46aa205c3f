"""The walking pattern: footsteps -> linear ZMP reference -> CoM by preview control -> feet.

Everything is sampled on one time grid ``0, dt, 2 dt, ...`` (paper B: dt = 10 ms) in the world
frame of :mod:`zmpkit.walking.footsteps`. The defaults are paper B's walk: 20 cm/s straight
ahead, 0.5 s steps, for 10 s, CoM height 0.26 m; a robot's own are its
:class:`~zmpkit.robots.robot.WalkingDefaults`. A correction of the
ZMP reference (paper B, Algorithms 1 and 2, half-sine or sawtooth offsets) enters through
``zmp_offset`` and is tracked instead of the linear reference.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.footsteps import (
    FootstepPlan,
    GaitParameters,
    Side,
    StepLimits,
    WalkCommand,
    plan_footsteps,
)
from zmpkit.walking.preview import (
    CoMTrajectory,
    PreviewController,
    PreviewGains,
    PreviewParameters,
    compute_preview_gains,
)
from zmpkit.walking.swing import DEFAULT_STEP_HEIGHT_M, FeetTrajectories, foot_trajectories
from zmpkit.walking.zmp_reference import ZmpReference, linear_zmp_reference, sample_times

__all__ = [
    "DEFAULT_COM_HEIGHT_M",
    "DEFAULT_CONTROL_PERIOD_S",
    "PatternConfig",
    "WalkingPattern",
    "generate_pattern",
    "pattern_sample_times",
]

#: Paper B's motion frame (the robot's DCM cycle) [s] (paper B footnote 5).
DEFAULT_CONTROL_PERIOD_S = 0.01
#: Paper B's CoM height of the 3D-LIPM walk [m].
DEFAULT_COM_HEIGHT_M = 0.26
#: Default preview horizon [s].
DEFAULT_PREVIEW_HORIZON_S = 1.6


@dataclass(frozen=True)
class PatternConfig:
    """Everything that defines a walking pattern.

    Attributes:
        command: commanded velocity (v_x [m/s], v_y [m/s], omega [rad/s]).
        duration_s: walking time [s]; None when ``n_steps`` is given.
        n_steps: number of steps, start and closing step included; None for ``duration_s``.
        gait: step timing and nominal foot separation.
        limits: step limits and sole size.
        first_side: first swing foot, or None for the planner's choice.
        control_period_s: sampling period of every output [s].
        com_height_m: z_c of the cart-table model [m].
        preview_horizon_s: preview horizon [s].
        error_weight: Q_e of the preview cost.
        jerk_weight: R of the preview cost.
        step_height_m: peak swing height [m].
        zmp_forward_m: where in each sole the ZMP reference sits, ahead of the sole's centre
            along it [m] (paper B: 0, the centre); within a quarter of the sole's length.
    """

    command: WalkCommand = field(default_factory=WalkCommand)
    duration_s: float | None = 10.0
    n_steps: int | None = None
    gait: GaitParameters = field(default_factory=GaitParameters)
    limits: StepLimits = field(default_factory=StepLimits)
    first_side: Side | None = None
    control_period_s: float = DEFAULT_CONTROL_PERIOD_S
    com_height_m: float = DEFAULT_COM_HEIGHT_M
    preview_horizon_s: float = DEFAULT_PREVIEW_HORIZON_S
    error_weight: float = 1.0
    jerk_weight: float = 1e-6
    step_height_m: float = DEFAULT_STEP_HEIGHT_M
    zmp_forward_m: float = 0.0

    def __post_init__(self) -> None:
        _validate.non_negative("PatternConfig.step_height_m", self.step_height_m, "m")
        quarter = self.limits.foot.length_m / 4
        if not abs(_validate.finite("PatternConfig.zmp_forward_m", self.zmp_forward_m)) <= quarter:
            raise ParameterError(
                f"PatternConfig.zmp_forward_m must lie within a quarter of the sole's length "
                f"(±{quarter:.4g} m), got {self.zmp_forward_m} m"
            )
        _validate.positive("PatternConfig.com_height_m", self.com_height_m, "m")
        _validate.positive("PatternConfig.preview_horizon_s", self.preview_horizon_s, "s")
        dt = _validate.positive("PatternConfig.control_period_s", self.control_period_s, "s")
        if dt > self.gait.single_support_s:
            raise ParameterError(
                f"PatternConfig.control_period_s must be <= the single-support time "
                f"{self.gait.single_support_s} s, got {dt} s"
            )
        self.preview_parameters()  # validates the remaining preview fields

    def preview_parameters(self) -> PreviewParameters:
        """The cart-table model and weights of this configuration."""
        return PreviewParameters(
            sampling_period_s=self.control_period_s,
            com_height_m=self.com_height_m,
            horizon_s=self.preview_horizon_s,
            error_weight=self.error_weight,
            jerk_weight=self.jerk_weight,
        )

    def plan(self) -> FootstepPlan:
        """The footstep plan of this configuration."""
        return plan_footsteps(
            self.command,
            self.gait,
            self.limits,
            n_steps=self.n_steps,
            duration_s=self.duration_s,
            first_side=self.first_side,
        )


@dataclass(frozen=True)
class WalkingPattern:
    """A planned walk, all signals on ``time_s``.

    Attributes:
        config: what was asked.
        footsteps: the footstep plan.
        linear_zmp_reference: paper B's linear reference, before any offset.
        zmp_offset_in_world: offset added to it [m], shape (N, 2).
        com: the CoM planned by preview control for reference + offset.
        feet: swing-foot trajectories and torso yaw.
        gains: the preview gains used.
    """

    config: PatternConfig
    footsteps: FootstepPlan
    linear_zmp_reference: ZmpReference
    zmp_offset_in_world: NDArray[np.float64]
    com: CoMTrajectory
    feet: FeetTrajectories
    gains: PreviewGains

    @property
    def time_s(self) -> NDArray[np.float64]:
        """Sample times [s], shape (N,)."""
        return self.linear_zmp_reference.time_s

    @property
    def zmp_reference_in_world(self) -> NDArray[np.float64]:
        """The tracked reference, linear reference + offset [m], shape (N, 2)."""
        return self.com.zmp_reference_in_world

    @property
    def com_position_in_world(self) -> NDArray[np.float64]:
        """CoM (x, y, z) with z = z_c [m], shape (N, 3)."""
        xy = self.com.com_position_in_world
        return np.column_stack([xy, np.full(xy.shape[0], self.com.com_height_m)])


def pattern_sample_times(config: PatternConfig) -> NDArray[np.float64]:
    """The time grid a pattern of ``config`` will have [s], e.g. to build ``zmp_offset``."""
    return sample_times(config.plan().duration_s, config.control_period_s)


def generate_pattern(
    config: PatternConfig | None = None,
    zmp_offset: ArrayLike | None = None,
    *,
    gains: PreviewGains | None = None,
) -> WalkingPattern:
    """Plan footsteps, ZMP reference, CoM, feet and torso for one walk.

    Args:
        config: the walk; defaults to paper B's 20 cm/s, 0.5 s steps, 10 s.
        zmp_offset: optional correction added to the linear reference [m], shape (N, 2)
            with N = len(pattern_sample_times(config)).
        gains: preview gains to reuse (e.g. ``pattern.gains`` of an earlier call in a
            compensation loop); computed from ``config`` when None. Must have been computed
            for ``config.preview_parameters()``.

    Returns:
        The pattern; ``com.zmp_in_world`` is the cart-table ZMP of the planned CoM.
    """
    config = config or PatternConfig()
    plan = config.plan()
    reference = linear_zmp_reference(plan, config.control_period_s, config.zmp_forward_m)
    n = reference.time_s.size
    if zmp_offset is None:
        offset = np.zeros((n, 2))
    else:
        offset = _validate.finite_array("zmp_offset", zmp_offset, (n, 2)).copy()
    offset.setflags(write=False)
    gains = _gains_for(config, gains)
    com = PreviewController(gains).run(
        reference.zmp_x_in_world + offset[:, 0], reference.zmp_y_in_world + offset[:, 1]
    )
    feet = foot_trajectories(plan, config.control_period_s, config.step_height_m)
    return WalkingPattern(config, plan, reference, offset, com, feet, gains)


def _gains_for(config: PatternConfig, gains: PreviewGains | None) -> PreviewGains:
    wanted = config.preview_parameters()
    if gains is None:
        return compute_preview_gains(wanted)
    if gains.parameters != wanted:
        raise ParameterError(
            f"gains were computed for {gains.parameters}, but the config needs {wanted}"
        )
    return gains
