"""The virtual NAO as a registry entry: :data:`NAO`, a :class:`~zmpkit.robots.robot.Robot`.

Walking: zmpkit's walk at a 0.25 m CoM height (:data:`NAO_WALK_COM_HEIGHT_M`), 10 ms motion
frames (paper B footnote 5), hips 0.100 m apart, the IK on the rigid design model with a
walking crouch (hip and ankle pitch −0.45 rad, knee 0.90 rad: a CoM about 0.26 m high,
nao-parameters.md §1). NAO has no standing-balance model in zmpkit.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from zmpkit.robots.ik_settings import IkSettings
from zmpkit.robots.nao import fit_catalogue
from zmpkit.robots.nao import geometry as geo
from zmpkit.robots.nao.fit_fields import NAO_FIELD_RULE
from zmpkit.robots.nao.model import (
    NAO_DRIVEN_JOINTS,
    NAO_LEG_JOINTS,
    NAO_WALK_COM_HEIGHT_M,
    nao_feet_mounts,
)
from zmpkit.robots.nao.robot import (
    NAO_CONTACT_FORCE_THRESHOLD_N,
    NAO_SERVO_LIMITS,
    nao_ik_mjcf,
    nao_robot,
)
from zmpkit.robots.nao.truth import DEFAULT_TRUTH_PATH, NaoTruth, load_truth, truth_from_doc
from zmpkit.robots.robot import FitSpec, Robot, TruthSpec, WalkingDefaults
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.world import Simulation

__all__ = [
    "NAO",
    "NAO_CONTROL_PERIOD_S",
    "NAO_CROUCH_POSTURE_RAD",
    "NAO_PLANNER_SOLE_M",
    "make_nao",
]

NAO_CROUCH_POSTURE_RAD: Mapping[str, float] = {
    f"{side}{joint}": angle
    for side in ("L", "R")
    for joint, angle in (("HipPitch", -0.45), ("KneePitch", 0.90), ("AnklePitch", -0.45))
}
"""Walking crouch whose CoM is 0.26 m high (nao-parameters.md §1) [rad]."""
NAO_CONTROL_PERIOD_S = 0.01
"""NAO's motion frame (DCM cycle) [s] (paper B footnote 5)."""

NAO_PLANNER_SOLE_M = (0.16, 0.09)
"""The footstep planner's NAO sole [m]: its 0.158 × 0.088 m outline (geometry) rounded up,
which keeps a little clearance between the feet."""

NAO = Robot(
    name="nao",
    title="NAO",
    summary="SoftBank NAO H25 V5, 5.3 kg kid-size humanoid (paper B): walking",
    source="nao",
    describe=nao_robot,
    driven_joints=NAO_DRIVEN_JOINTS,
    feet_mounts=nao_feet_mounts,
    truth=TruthSpec(DEFAULT_TRUTH_PATH, load_truth, truth_from_doc, NaoTruth),
    servo_limits=NAO_SERVO_LIMITS,
    contact_force_threshold_n=NAO_CONTACT_FORCE_THRESHOLD_N,
    walking=WalkingDefaults(
        com_height_m=NAO_WALK_COM_HEIGHT_M,
        control_period_s=NAO_CONTROL_PERIOD_S,
        foot_separation_m=2.0 * geo.HIP_OFFSET_Y_M,
        max_step_length_m=0.12,
        sole_size_m=NAO_PLANNER_SOLE_M,
        ik_settings=IkSettings(
            joint_names=NAO_LEG_JOINTS, posture_rad=dict(NAO_CROUCH_POSTURE_RAD)
        ),
        ik_mjcf=nao_ik_mjcf,
        series_joints=tuple(
            f"{s}{j}" for s in ("L", "R") for j in ("HipPitch", "KneePitch", "AnklePitch")
        ),
    ),
    fit=FitSpec(
        fit_catalogue.FIT_CATALOGUE, fit_catalogue.QUICK_FIT_PARAMETERS, "walk", NAO_FIELD_RULE
    ),
)
"""The virtual NAO."""


def make_nao(
    effects: EffectSet | str = "all",
    truth: NaoTruth | str | Path | None = None,
    seed: int = 0,
) -> Simulation:
    """:data:`NAO`'s :meth:`~zmpkit.robots.robot.Robot.make_simulation`: standing, legs straight."""
    return NAO.make_simulation(effects, truth, seed)
