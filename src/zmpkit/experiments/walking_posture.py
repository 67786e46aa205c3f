r"""A walking posture a user's robot can hold: torso lean, crouch and where the ZMP is planned.

A user's robot walks by default in an upright crouch (the hips lowered by
:data:`~zmpkit.robots.user_walking.CROUCH_FRACTION` of the leg) with the planned ZMP at each
sole's centre, as paper B's walking robot does. Some legs cannot: the Berkeley Humanoid's ankles sit
31 mm behind its sole centres and bend only 0.52 rad (30°) upwards, so holding its CoM over
the sole centres in that crouch takes more dorsiflexion than its ankles have, and the
whole-body IK leaves the plan by 12.6 mm (its walk is refused). Its own standing keyframe
shows the way out: the torso leans forward, the hips go back, the shins stay steeper.

:func:`choose_walking_posture` looks first at the default crouch: when every leg joint is
at least :data:`CROUCH_MARGIN_RAD` from its limits there (a walk swings the stance ankle
about 0.15 rad around it), the default stands. Otherwise it probes the walk the robot will
be asked for (its default speed, 0.5 s steps, :data:`PROBE_DURATION_S`) with the whole-body
IK, the plan itself and nothing simulated: first the default posture, then, only if the IK
cannot follow it within
:data:`~zmpkit.experiments.walk.IK_REALISABLE_M`, the candidates of :func:`candidates` in
order (the ZMP at the sole centre, then under the ankle; the torso upright, then leaning
forward by 0.2, 0.4, 0.6 rad; the crouch 8 % then 6 % of the leg), keeping the first whose
plan the IK follows with every leg joint off its limits. ``zmpkit robot init`` writes the
choice into the robot file (``walking.torso_pitch``, ``walking.crouch``,
``walking.zmp_forward``), saying why; a robot no candidate fits is left as it was, and its
walk is refused with the joints that hold it back.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from zmpkit.experiments.walk import AT_LIMIT_RAD, IK_REALISABLE_M
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.robots.robot import Robot
from zmpkit.robots.robot_file import RobotFile
from zmpkit.robots.user_walking import CROUCH_FRACTION, crouch, leg_length_m, pitch_joints
from zmpkit.sim.names import sole_site
from zmpkit.walking.ik import solve_walking_ik
from zmpkit.walking.pattern import generate_pattern

__all__ = [
    "CROUCH_MARGIN_RAD",
    "PROBE_DURATION_S",
    "PostureChoice",
    "PostureProbe",
    "WalkingPosture",
    "ankle_forward_m",
    "candidates",
    "choose_walking_posture",
    "crouch_margin_rad",
    "probe_posture",
]

CROUCH_MARGIN_RAD = 0.1
"""A default crouch whose leg joints all keep this far from their limits is not probed [rad]."""
PROBE_DURATION_S = 4.0
"""Walking time of the probe [s]: the start, the first steps at full speed and the stop."""
TORSO_PITCHES_RAD = (0.0, 0.2, 0.4, 0.6)
"""The forward leans tried, upright first [rad]."""
CROUCH_FRACTIONS = (CROUCH_FRACTION, 0.06)
"""The crouches tried, as shares of the leg length [-]."""


@dataclass(frozen=True)
class WalkingPosture:
    """How a robot stands to walk.

    Attributes:
        torso_pitch_rad: the torso's forward lean [rad].
        crouch: the hips lowered by this share of the leg length [-].
        zmp_forward_m: the planned ZMP's place in each sole, ahead of its centre [m].
    """

    torso_pitch_rad: float = 0.0
    crouch: float = CROUCH_FRACTION
    zmp_forward_m: float = 0.0

    def describe(self) -> str:
        """``torso pitch 0.4 rad, crouch 6 % of the leg, ZMP 31 mm behind the sole centre``."""
        d = self.zmp_forward_m
        where = (
            "at the sole centre"
            if d == 0.0
            else f"{1e3 * abs(d):.0f} mm {'ahead of' if d > 0 else 'behind'} the sole centre"
        )
        return (
            f"torso pitch {self.torso_pitch_rad:g} rad, crouch {100 * self.crouch:g} % of the "
            f"leg, ZMP {where}"
        )


@dataclass(frozen=True)
class PostureProbe:
    """How well the whole-body IK follows the probe walk in one posture.

    Attributes:
        posture: the posture probed.
        ik_error_m: the larger of the IK's largest CoM and sole errors [m].
        least_margin_rad: the smallest distance of a leg joint from its range's ends over
            the walk [rad] (negative: beyond it).
        tightest_joint: the joint with that margin.
    """

    posture: WalkingPosture
    ik_error_m: float
    least_margin_rad: float
    tightest_joint: str

    @property
    def realisable(self) -> bool:
        """The IK follows the plan within :data:`~zmpkit.experiments.walk.IK_REALISABLE_M`."""
        return self.ik_error_m <= IK_REALISABLE_M

    @property
    def comfortable(self) -> bool:
        """Realisable with every leg joint off its limits."""
        return self.realisable and self.least_margin_rad > AT_LIMIT_RAD

    def describe(self) -> str:
        """``IK 12.6 mm off the plan, LL_FFE 0.000 rad from its limit``."""
        margin = self.least_margin_rad if abs(self.least_margin_rad) >= 5e-4 else 0.0
        return (
            f"IK {1e3 * self.ik_error_m:.1f} mm off the plan, {self.tightest_joint} "
            f"{margin:.3f} rad from its limit"
        )


@dataclass(frozen=True)
class PostureChoice:
    """The probe of the default posture and, when it failed, the posture chosen.

    Attributes:
        default: the default posture's probe; None when its crouch keeps every leg joint
            :data:`CROUCH_MARGIN_RAD` off its limits (not probed).
        chosen: the first comfortable candidate's probe; None when the default is
            realisable or when no candidate is comfortable.
        tried: how many candidates were probed.
    """

    default: PostureProbe | None
    chosen: PostureProbe | None
    tried: int


def ankle_forward_m(robot: Robot, file: RobotFile) -> float:
    """Where the ankles stand along the soles, ahead of their centres (mean of both) [m].

    The ankle is each leg's last pitch joint; the model faces +x at its initial pose.
    """
    model = robot.ik_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    ankles = pitch_joints(model, data, file)[2::3]
    offsets = [
        float(data.xanchor[model.joint(ankle).id][0] - data.site(sole_site(side)).xpos[0])
        for ankle, side in zip(ankles, ("left", "right"), strict=True)
    ]
    return float(np.mean(offsets))


def _least_margin(
    model: mujoco.MjModel, angles_rad: Mapping[str, tuple[float, float]]
) -> tuple[float, str]:
    """The limited joint closest to its range's ends, and how close [rad].

    Returns ``(inf, "")`` when no joint is limited.

    Args:
        model: the model whose joint ranges count.
        angles_rad: joint → (smallest, largest) angle it takes [rad].
    """
    least = (math.inf, "")
    for name, (lowest, highest) in angles_rad.items():
        joint = model.joint(name).id
        if model.jnt_limited[joint]:
            low, high = (float(v) for v in model.jnt_range[joint])
            least = min(least, (min(lowest - low, high - highest), name))
    return least


def crouch_margin_rad(robot: Robot) -> float:
    """The smallest distance of a leg joint from its range's ends in the walking crouch [rad]."""
    settings = robot.require_walking().ik_settings
    angles = {name: settings.posture_rad.get(name, 0.0) for name in settings.joint_names}
    return _least_margin(robot.ik_model(), {n: (a, a) for n, a in angles.items()})[0]


def candidates(ankle_forward: float, quarter_sole_m: float) -> list[WalkingPosture]:
    """The postures tried after the default, in order (module docstring).

    The ZMP goes under the ankle at most a quarter of the sole from its centre.
    """
    under_ankle = float(np.clip(ankle_forward, -quarter_sole_m, quarter_sole_m))
    points = (0.0, under_ankle) if abs(under_ankle) > 1e-3 else (0.0,)
    out = [
        WalkingPosture(pitch, fraction, point)
        for point in points
        for pitch in TORSO_PITCHES_RAD
        for fraction in CROUCH_FRACTIONS
    ]
    return [p for p in out if p != WalkingPosture()]


def probe_posture(robot: Robot, file: RobotFile, posture: WalkingPosture) -> PostureProbe:
    """Solve the probe walk's IK with ``robot`` standing in ``posture``."""
    model = robot.ik_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    bent = crouch(model, file, posture.crouch * leg_length_m(model, data, file),
                  posture.torso_pitch_rad)  # fmt: skip
    walking = robot.require_walking()
    settings = dataclasses.replace(
        walking.ik_settings,
        posture_rad=bent.posture_rad,
        torso_pitch_rad=posture.torso_pitch_rad,
    )
    walking = dataclasses.replace(
        walking,
        ik_settings=settings,
        com_height_m=bent.com_height_m,
        zmp_forward_m=posture.zmp_forward_m,
    )
    config = WalkConfig(
        robot=dataclasses.replace(robot, walking=walking), duration_s=PROBE_DURATION_S
    )
    trajectory = solve_walking_ik(generate_pattern(config.pattern_config()), model, settings)
    q = trajectory.q_rad
    ranges = {
        name: (float(q[:, k].min()), float(q[:, k].max()))
        for k, name in enumerate(trajectory.joint_names)
    }
    margin, joint_name = _least_margin(model, ranges)
    error = max(trajectory.max_com_error_m, trajectory.max_foot_error_m)
    return PostureProbe(posture, error, margin, joint_name)


def choose_walking_posture(robot: Robot, file: RobotFile) -> PostureChoice:
    """The default posture's probe, and a comfortable one when the default is not realisable.

    Args:
        robot: the robot built from ``file`` (it walks).
        file: its robot file, whose ``walking:`` gives no posture of its own.
    """
    if crouch_margin_rad(robot) >= CROUCH_MARGIN_RAD:
        return PostureChoice(None, None, 0)
    default = probe_posture(robot, file, WalkingPosture())
    if default.realisable:
        return PostureChoice(default, None, 0)
    quarter = robot.require_walking().sole_size_m[0] / 4
    tried = 0
    for posture in candidates(ankle_forward_m(robot, file), quarter):
        tried += 1
        probe = probe_posture(robot, file, posture)
        if probe.comfortable:
            return PostureChoice(default, probe, tried)
    return PostureChoice(default, None, tried)
