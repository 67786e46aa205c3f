"""NAO H25 V5 numbers for a primitives-only model (``shared/robots/nao-parameters.md``).

Lengths, joint axes and limits and link inertials are those of the public URDF (key U of the
parameters file, BSD); the sole outline is the Nao Devils' (ND). Frames follow NAO: x
forward, y left, z up; the ``torso`` frame is the URDF base link. Only the left side is
listed; the right side mirrors y (CoM y, roll and yaw limits).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "ANKLE_TO_SOLE_M",
    "ARM",
    "HEAD",
    "HEAD_ORIGIN_M",
    "HIP_OFFSET_Y_M",
    "HIP_OFFSET_Z_M",
    "IMU_POSITION_M",
    "LEG_JOINTS",
    "LEG_LINKS",
    "SHOULDER_OFFSET_Y_M",
    "SHOULDER_OFFSET_Z_M",
    "SOLE_CENTRE_AHEAD_OF_ANKLE_M",
    "SOLE_LENGTH_M",
    "SOLE_WIDTH_M",
    "THIGH_LENGTH_M",
    "TIBIA_LENGTH_M",
    "TORSO",
    "Inertial",
    "LegJoint",
]

HIP_OFFSET_Y_M = 0.050
"""Lateral offset of each HipYawPitch axis from the torso origin [m] (U)."""
HIP_OFFSET_Z_M = 0.085
"""Drop of the hip axes below the torso origin [m] (U)."""
THIGH_LENGTH_M = 0.100
"""Hip pitch axis to knee axis [m] (U)."""
TIBIA_LENGTH_M = 0.1029
"""Knee axis to ankle pitch axis [m] (U)."""
ANKLE_TO_SOLE_M = 0.04511
"""Ankle axes to the sole plane (FootHeight) [m] (U; the V3.3 docs say 0.04519)."""
SOLE_LENGTH_M = 0.158
"""Sole outline length, heel to toe [m] (ND: 104 + 54 mm)."""
SOLE_WIDTH_M = 0.088
"""Sole outline width [m] (ND: 44 + 44 mm)."""
SOLE_CENTRE_AHEAD_OF_ANKLE_M = 0.5 * SOLE_LENGTH_M - 0.054
"""The sole centre lies this far ahead of the ankle projection [m] (ankle 54 mm from the heel)."""
SHOULDER_OFFSET_Y_M = 0.098
"""Lateral offset of the shoulder pitch axes [m] (U)."""
SHOULDER_OFFSET_Z_M = 0.100
"""Height of the shoulder pitch axes above the torso origin [m] (U)."""
HEAD_ORIGIN_M = (0.0, 0.0, 0.1265)
"""HeadYaw axis in the torso frame (NeckOffsetZ) [m] (U)."""
IMU_POSITION_M = (-0.008, 0.00606, 0.027)
"""Inertial unit in the torso frame [m] (Aldebaran docs; not in the parameters file, ASSUMED)."""


@dataclass(frozen=True)
class Inertial:
    """Mass, centre of mass and inertia at the CoM (principal axes = link axes).

    Attributes:
        mass: [kg].
        com: CoM in the link frame [m].
        inertia: (Ixx, Iyy, Izz) at the CoM [kg·m²].
    """

    mass: float
    com: tuple[float, float, float]
    inertia: tuple[float, float, float]

    def mirrored(self) -> Inertial:
        """The right-side link: CoM y negated."""
        x, y, z = self.com
        return Inertial(self.mass, (x, -y, z), self.inertia)


@dataclass(frozen=True)
class LegJoint:
    """One leg joint of the left leg, the body it moves and where its frame sits.

    Attributes:
        stem: joint name without the side letter, e.g. ``"HipPitch"``.
        axis: joint axis in the (unrotated) joint frame [-].
        origin: joint frame in its parent link frame [m] (y of the left leg).
        range_left: limits of the left joint [rad].
        range_right: limits of the right joint [rad].
    """

    stem: str
    axis: tuple[float, float, float]
    origin: tuple[float, float, float]
    range_left: tuple[float, float]
    range_right: tuple[float, float]


_DIAG = 0.7071067811865476
LEG_JOINTS: tuple[LegJoint, ...] = (
    LegJoint(
        "HipYawPitch",
        (0.0, _DIAG, -_DIAG),
        (0.0, HIP_OFFSET_Y_M, -HIP_OFFSET_Z_M),
        (-1.14529, 0.740718),
        (-1.14529, 0.740718),
    ),
    LegJoint(
        "HipRoll", (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), (-0.379435, 0.79046), (-0.79046, 0.379435)
    ),
    LegJoint(
        "HipPitch", (0.0, 1.0, 0.0), (0.0, 0.0, 0.0), (-1.53589, 0.48398), (-1.53589, 0.48398)
    ),
    LegJoint(
        "KneePitch",
        (0.0, 1.0, 0.0),
        (0.0, 0.0, -THIGH_LENGTH_M),
        (-0.0923279, 2.11255),
        (-0.0923279, 2.11255),
    ),
    LegJoint(
        "AnklePitch",
        (0.0, 1.0, 0.0),
        (0.0, 0.0, -TIBIA_LENGTH_M),
        (-1.18944, 0.922581),
        (-1.1863, 0.932006),
    ),
    LegJoint(
        "AnkleRoll", (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), (-0.397761, 0.768992), (-0.768992, 0.397761)
    ),
)
"""The six leg joints, hip to ankle (U §3)."""

LEG_LINKS: dict[str, Inertial] = {
    "HipYawPitch": Inertial(0.06981, (-0.00781, -0.01114, 0.02661), (2.341e-5, 4.764e-5, 4.970e-5)),
    "HipRoll": Inertial(0.14053, (-0.01549, 0.00029, -0.00515), (2.384e-5, 6.083e-5, 5.437e-5)),
    "HipPitch": Inertial(0.38968, (0.00138, 0.00221, -0.05373), (5.098e-4, 4.654e-4, 3.011e-4)),
    "KneePitch": Inertial(0.30142, (0.00453, 0.00225, -0.04936), (4.462e-4, 3.881e-4, 1.855e-4)),
    "AnklePitch": Inertial(0.13416, (0.00045, 0.00029, 0.00685), (3.220e-5, 6.794e-5, 5.483e-5)),
    "AnkleRoll": Inertial(0.17184, (0.02542, 0.0033, -0.03239), (8.729e-5, 3.530e-4, 4.129e-4)),
}
"""Left-leg link inertials, keyed by the joint that moves the link (U §4)."""

TORSO = Inertial(1.04956, (-0.00413, 0.0, 0.04342), (3.0836e-3, 2.8835e-3, 1.5924e-3))
"""The torso link (U §4)."""
HEAD = Inertial(0.68375, (-0.0010, 0.0, 0.0434), (1.42e-3, 1.28e-3, 9.91e-4))
"""Neck + head lumped, in the HeadYaw frame (parameters file §4, lumped bodies)."""
ARM = Inertial(0.57858, (0.002, 0.0058, -0.0952), (4.22e-3, 4.13e-3, 3.33e-4))
"""One arm hanging (ShoulderPitch 1.57 rad), lumped, in the left shoulder frame; the
forward-arm inertia (3.33e-4, 4.13e-3, 4.22e-3) turned a quarter-turn about y (§4)."""
