"""The walking IK's settings: which joints it reports, which frames it tracks, its weights.

A robot gives its own (:attr:`~zmpkit.robots.robot.WalkingDefaults.ik_settings`: its leg
joints, sole-centre sites, torso body and walking crouch); the solver is
:func:`zmpkit.walking.ik.solve_walking_ik`, which re-exports this class.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from zmpkit import _validate
from zmpkit.errors import ModelError
from zmpkit.sim.names import sole_site

__all__ = ["IkSettings"]


@dataclass(frozen=True)
class IkSettings:
    """Frames, weights and stopping rule of the walking IK.

    Attributes:
        joint_names: the joints reported in the trajectory, in order.
        sole_sites: foot side → site at the sole centre on the sole plane.
        torso_body: body whose orientation follows the planned torso.
        torso_pitch_rad: the torso's forward lean while walking, about the walk's lateral
            axis [rad] (0: upright).
        posture_rad: nominal posture [rad] (joints not named: 0); also the start guess.
            Default: the zero pose; a robot gives its own (e.g. a walking crouch).
        foot_cost: weight of the feet position [1/m] and orientation [1/rad] errors.
        com_cost: weight of the CoM error [1/m].
        torso_cost: weight of the torso orientation error [1/rad].
        posture_cost: weight of the posture error [1/rad].
        equality_cost: weight of the joint-equality residuals.
        damping: Levenberg–Marquardt damping of the QP [-].
        tolerance_m: stop iterating a sample when the CoM and feet errors are below this [m].
        max_iterations: iterations per sample (the first sample gets ten times as many).
        solver: the QP solver mink calls.
    """

    joint_names: tuple[str, ...]
    sole_sites: Mapping[str, str] = field(
        default_factory=lambda: {side: sole_site(side) for side in ("left", "right")}
    )
    torso_body: str = "torso"
    torso_pitch_rad: float = 0.0
    posture_rad: Mapping[str, float] = field(default_factory=dict)
    foot_cost: float = 10.0
    com_cost: float = 10.0
    torso_cost: float = 1.0
    posture_cost: float = 1e-3
    equality_cost: float = 100.0
    damping: float = 1e-6
    tolerance_m: float = 2e-5
    max_iterations: int = 8
    solver: str = "daqp"

    def __post_init__(self) -> None:
        for name in ("foot_cost", "com_cost", "torso_cost", "posture_cost", "tolerance_m"):
            _validate.positive(f"IkSettings.{name}", getattr(self, name))
        _validate.non_negative("IkSettings.damping", self.damping)
        if self.max_iterations < 1:
            raise ModelError(f"IkSettings.max_iterations must be >= 1, got {self.max_iterations}")
