r"""Where a swing foot can land: the legs' reach and the no-crossing limit, from the robot's model.

A leg of straight length ``L`` (hip joint to sole centre with every leg joint at zero, the
URDF/MJCF convention of a straight leg) whose hip stands ``h`` above the sole in the walking
posture reaches a sole ``r = ρ \sqrt{L^2 - h^2}`` from below its hip, ``ρ < 1`` keeping the
knee off its straight (singular) pose. At touchdown the pelvis lies about midway between the
feet (the LIPM's CoM between the soles), so a landing ``(Δx, l)`` relative to the stance
sole — along it, and outwards (towards the swing foot's side) — is within both legs' reach
when

.. math:: \Big(\frac{Δx}{2}\Big)^2 + \Big(\frac{l}{2} - w_h\Big)^2 \le r^2,

``w_h`` the hips' half distance. Its bounding box gives ``|Δx| ≤ 2r`` and ``l ≤ 2(w_h + r)``;
the legs must not cross or collide, so ``l ≥ w + c`` (the sole width and the planner's
clearance, :attr:`~zmpkit.walking.gait.StepLimits.min_foot_separation_m`). A landing is
first limited to the box (:mod:`zmpkit.walking.capture_step`), then drawn radially into the
ellipse (:meth:`StepReach.limit`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ModelError
from zmpkit.robots.ik_settings import IkSettings

__all__ = ["DEFAULT_REACH_MARGIN", "StepReach", "step_reach"]

DEFAULT_REACH_MARGIN = 0.6
"""ρ: the share of the straight leg's horizontal reach a recovery step uses [-]."""


@dataclass(frozen=True)
class StepReach:
    """Where a swing foot may land relative to the stance sole (module docstring).

    Attributes:
        leg_reach_m: r, how far from below its hip a sole reaches [m].
        hip_half_width_m: w_h, half the distance between the hips [m].
        min_lateral_m: the least outward distance of the landing from the stance sole, so
            that the legs do not cross [m].
    """

    leg_reach_m: float
    hip_half_width_m: float
    min_lateral_m: float

    def __post_init__(self) -> None:
        _validate.positive("StepReach.leg_reach_m", self.leg_reach_m, "m")
        _validate.non_negative("StepReach.hip_half_width_m", self.hip_half_width_m, "m")
        _validate.positive("StepReach.min_lateral_m", self.min_lateral_m, "m")

    @property
    def max_along_m(self) -> float:
        """Largest |Δx| of a landing, forwards or backwards [m]."""
        return 2.0 * self.leg_reach_m

    @property
    def max_lateral_m(self) -> float:
        """Largest outward distance of a landing from the stance sole [m]."""
        return 2.0 * (self.hip_half_width_m + self.leg_reach_m)

    def shift_box(
        self, along_m: float, lateral_m: float, sign: float
    ) -> tuple[float, float, float, float]:
        """``(lo_x, hi_x, lo_y, hi_y)``: the shifts of a planned landing the legs reach [m].

        ``along_m`` and ``lateral_m`` the planned landing in the stance sole's frame
        (:mod:`~zmpkit.walking.planned_steps`), ``sign`` s (+1 left swing); x along the
        stance sole, y across it (world side); each box holds 0, the planned landing.
        """
        lo_x, hi_x = -self.max_along_m - along_m, self.max_along_m - along_m
        lo_l, hi_l = self.min_lateral_m - lateral_m, self.max_lateral_m - lateral_m
        lo_x, lo_l = (lo_x if lo_x < 0.0 else 0.0), (lo_l if lo_l < 0.0 else 0.0)
        hi_x, hi_l = (hi_x if hi_x > 0.0 else 0.0), (hi_l if hi_l > 0.0 else 0.0)
        return (lo_x, hi_x, lo_l, hi_l) if sign > 0.0 else (lo_x, hi_x, -hi_l, -lo_l)

    def limit(self, along_m: float, lateral_m: float) -> tuple[float, float]:
        """The landing ``(Δx, l)`` [m] drawn into the reach ellipse and above the no-crossing line.

        Scalar arithmetic only (it runs in the control tick).
        """
        r, w = self.leg_reach_m, self.hip_half_width_m
        u, v = 0.5 * along_m, 0.5 * lateral_m - w
        norm = math.sqrt(u * u + v * v)
        if norm > r:
            along_m, lateral_m = 2.0 * u * r / norm, 2.0 * (w + v * r / norm)
        floor = self.min_lateral_m
        return along_m, (floor if lateral_m < floor else lateral_m)


def _hip_joint(model: mujoco.MjModel, site: int, leg_joints: set[str]) -> int:
    """The leg joint nearest the root on the way from the sole's body to the root."""
    body, hip = int(model.site_bodyid[site]), -1
    while body > 0:
        for joint in range(
            model.body_jntadr[body], model.body_jntadr[body] + model.body_jntnum[body]
        ):
            if model.joint(joint).name in leg_joints:
                hip = joint
        body = int(model.body_parentid[body])
    if hip < 0:
        raise ModelError(
            f"no leg joint between the sole site {model.site(site).name!r} and the root"
        )
    return hip


def _posed(model: mujoco.MjModel, qpos: NDArray[np.float64]) -> mujoco.MjData:
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    return data


def step_reach(
    model: mujoco.MjModel,
    settings: IkSettings,
    walking_qpos: NDArray[np.float64],
    min_lateral_m: float,
    margin: float = DEFAULT_REACH_MARGIN,
) -> StepReach:
    """The reach of ``model``'s legs in the walking posture (module docstring).

    Args:
        model: the robot's design model (the IK's), floating base first.
        settings: its leg joints and sole sites.
        walking_qpos: the model standing in its walking posture (the IK's first frame).
        min_lateral_m: the least outward distance between the soles (sole width and
            clearance) [m].
        margin: ρ, in (0, 1].
    """
    _validate.in_range("margin", margin, 1e-3, 1.0)
    straight_q = np.array(walking_qpos, dtype=np.float64)
    legs = set(settings.joint_names)
    for name in legs:
        straight_q[int(model.joint(name).qposadr[0])] = 0.0
    walking, straight = _posed(model, walking_qpos), _posed(model, straight_q)
    reaches, hips_y = [], []
    for site_name in settings.sole_sites.values():
        site = int(model.site(site_name).id)
        hip = _hip_joint(model, site, legs)
        length = float(np.linalg.norm(straight.xanchor[hip] - straight.site_xpos[site]))
        height = float(walking.xanchor[hip][2] - walking.site_xpos[site][2])
        reaches.append(margin * math.sqrt(max(length * length - height * height, 0.0)))
        hips_y.append(float(walking.xanchor[hip][1]))
    reach = min(reaches)
    if reach <= 0.0:
        raise ModelError("the legs are straight in the walking posture: no step reaches further")
    half_width = 0.5 * (max(hips_y) - min(hips_y))
    return StepReach(reach, half_width, min_lateral_m)
