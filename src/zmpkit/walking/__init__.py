"""Walking pattern generation: footsteps, linear ZMP reference, preview control, swing feet.

The pipeline is :func:`generate_pattern`; each stage is also usable alone:
:func:`plan_footsteps` -> :func:`linear_zmp_reference` -> :class:`PreviewController` ->
:func:`foot_trajectories`.
"""

from __future__ import annotations

from zmpkit.walking.footsteps import (
    FootShape,
    Footstep,
    FootstepPlan,
    GaitParameters,
    Side,
    StepLimits,
    SupportPhase,
    WalkCommand,
    plan_footsteps,
)
from zmpkit.walking.pattern import (
    DEFAULT_CONTROL_PERIOD_S,
    PatternConfig,
    WalkingPattern,
    generate_pattern,
    pattern_sample_times,
)
from zmpkit.walking.preview import (
    CoMTrajectory,
    PreviewController,
    PreviewGains,
    PreviewParameters,
    cart_table_matrices,
    compute_preview_gains,
)
from zmpkit.walking.swing import (
    DEFAULT_STEP_HEIGHT_M,
    FeetTrajectories,
    FootTrajectory,
    foot_trajectories,
    minimum_jerk,
    swing_height,
)
from zmpkit.walking.zmp_reference import ZmpReference, linear_zmp_reference, sample_times

__all__ = [
    "DEFAULT_CONTROL_PERIOD_S",
    "DEFAULT_STEP_HEIGHT_M",
    "CoMTrajectory",
    "FeetTrajectories",
    "FootShape",
    "FootTrajectory",
    "Footstep",
    "FootstepPlan",
    "GaitParameters",
    "PatternConfig",
    "PreviewController",
    "PreviewGains",
    "PreviewParameters",
    "Side",
    "StepLimits",
    "SupportPhase",
    "WalkCommand",
    "WalkingPattern",
    "ZmpReference",
    "cart_table_matrices",
    "compute_preview_gains",
    "foot_trajectories",
    "generate_pattern",
    "linear_zmp_reference",
    "minimum_jerk",
    "pattern_sample_times",
    "plan_footsteps",
    "sample_times",
    "swing_height",
]
