"""TEO's rigid-body numbers, copied (numbers only) from the project's ``teo-parameters.md``.

Frames: x forward, y left, z up; zero pose = legs straight, arms hanging. Link inertials
are from the developer manual's ``dynamic_info_relative.csv`` (CoM in the link frame [m],
inertia at the CoM with root-frame axes [kg·m²], as ``Ixx Iyy Izz Ixy Ixz Iyz``). Link
lengths are the manual's ``lengths.csv`` (l9…l16). Values marked "L" in the parameters file
are used for the left side; otherwise the left side is the right mirrored in y.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "ANKLE_TO_SOLE_M",
    "ANKLE_TO_TOE_M",
    "ARM",
    "FT_HEIGHT_ABOVE_SOLE_M",
    "HEAD_LINKS",
    "HEEL_TO_ANKLE_M",
    "HIP_DROP_M",
    "HIP_LATERAL_M",
    "KNEE_TO_ANKLE_LATERAL_M",
    "LEG_JOINTS",
    "LEG_LINKS",
    "ROOT_TO_SHOULDER_M",
    "ROOT_TO_TRUNK_JOINTS_M",
    "SHANK_M",
    "SHOULDER_LATERAL_M",
    "SOLE_LENGTH_M",
    "SOLE_WIDTH_M",
    "THIGH_M",
    "TRUNK_LINKS",
    "Inertial",
    "LegJoint",
]

HIP_DROP_M = 0.092
"""l9: root waist → hip pitch/roll axes [m]."""
THIGH_M = 0.330
"""l10: hip → knee [m]."""
SHANK_M = 0.300
"""l11: knee → ankle [m]."""
ANKLE_TO_SOLE_M = 0.123005
"""l12: ankle axes → sole [m]."""
HIP_LATERAL_M = 0.146
"""l13: hip lateral offset from the midline [m]."""
KNEE_TO_ANKLE_LATERAL_M = 0.0175
"""l16: the ankle moves this far toward the midline below the knee [m]."""
ROOT_TO_TRUNK_JOINTS_M = 0.1932
"""l0: root waist → trunk joints [m]."""
ROOT_TO_SHOULDER_M = 0.4982
"""l0 + l1: root waist → shoulder level [m]."""
SHOULDER_LATERAL_M = 0.26292
"""Frontal-shoulder joint lateral offset from the midline (SDF) [m]."""
SOLE_LENGTH_M = 0.245
"""Sole length along x (zmpViewer-teo.ini "height") [m]."""
SOLE_WIDTH_M = 0.140
"""Sole width along y [m]."""
HEEL_TO_ANKLE_M = 0.07
"""Ankle projection from the heel edge (the "0.07 from one end" — assumed the heel;
unverified in the parameters file) [m]."""
ANKLE_TO_TOE_M = SOLE_LENGTH_M - HEEL_TO_ANKLE_M
"""Ankle projection to the toe edge [m]."""
FT_HEIGHT_ABOVE_SOLE_M = ANKLE_TO_SOLE_M - 0.113
"""JR3 frame height above the sole: l12 − 0.113 (SDF fixed joint 0.113 m below the ankle)
≈ 0.010 m. The balance code uses 0.03225 m and older code 0.0194 m; we use the SDF one."""


@dataclass(frozen=True)
class Inertial:
    """A link's mass [kg], CoM in its frame [m] and inertia at the CoM [kg·m²]."""

    mass: float
    com: tuple[float, float, float]
    inertia: tuple[float, float, float, float, float, float]


@dataclass(frozen=True)
class LegJoint:
    """One leg joint: name stem, axis, right-leg hard limits [deg], gear ratio [-]."""

    stem: str
    axis: tuple[float, float, float]
    range_deg: tuple[float, float]
    gear_ratio: float


LEG_JOINTS: tuple[LegJoint, ...] = (
    LegJoint("hip_axial", (0.0, 0.0, 1.0), (-37.79, 32.93), 400.0),
    LegJoint("hip_sagittal", (1.0, 0.0, 0.0), (-19.24, 17.49), 523.2),
    LegJoint("hip_frontal", (0.0, 1.0, 0.0), (-36.63, 47.28), 192.0),
    LegJoint("knee_frontal", (0.0, 1.0, 0.0), (-66.33, 87.43), 235.2),
    LegJoint("ankle_frontal", (0.0, 1.0, 0.0), (-28.12, 30.39), 270.4),
    LegJoint("ankle_sagittal", (1.0, 0.0, 0.0), (-24.96, 47.52), 235.2),
)
"""TEO's leg joint order (YARP rightLeg:0…5): axial hip z, sagittal hip x, frontal hip y,
knee y, frontal ankle y, sagittal ankle x. Ratios: harmonic drive × belt."""

LEG_LINKS: dict[str, dict[str, Inertial]] = {
    "right": {
        "hip_axial": Inertial(
            0.84945, (0.000089, -0.000389, -0.065985), (0.001564, 0.002645, 0.001706, 0, 2.5e-6, 0)
        ),
        "hip_sagittal": Inertial(
            1.45459, (-0.000636, 0.001058, 0.000349), (0.001546, 0.001192, 0.002270, -3e-6, 0, 0)
        ),
        "hip_frontal": Inertial(
            1.89152,
            (-0.010862, -0.000006, -0.161205),
            (0.015078, 0.015112, 0.007473, 0, -4.42e-4, 0),
        ),
        "knee_frontal": Inertial(
            1.94824, (-0.006614, -0.000411, -0.146413), (0.021862, 0.021411, 0.003844, 0, 3.2e-6, 0)
        ),
        "ankle_frontal": Inertial(
            1.50359, (0.002577, -0.013536, 0.000182), (0.001395, 0.001589, 0.002419, 6.9e-6, 0, 0)
        ),
        "ankle_sagittal": Inertial(
            3.1334,
            (0.01003, 0.000936, -0.0669),
            (0.007742, 0.014781, 0.013362, 4.56e-4, -1.852e-3, -1.48e-4),
        ),
    },
    "left": {
        "hip_axial": Inertial(
            0.84945, (0.000089, 0.000389, -0.065985), (0.001564, 0.002645, 0.001706, 0, 2.5e-6, 0)
        ),
        "hip_sagittal": Inertial(
            1.45459, (-0.00011, -0.000988, 0.000214), (0.001546, 0.001192, 0.002270, 3e-6, 0, 0)
        ),
        "hip_frontal": Inertial(
            1.89152,
            (-0.010862, 0.000006, -0.161205),
            (0.015078, 0.015112, 0.007473, 0, -4.42e-4, 0),
        ),
        "knee_frontal": Inertial(
            1.94824, (-0.006614, 0.000411, -0.146413), (0.021862, 0.021411, 0.003844, 0, 3.2e-6, 0)
        ),
        "ankle_frontal": Inertial(
            1.50359, (0.001999, 0.013793, 0.000035), (0.001392, 0.001590, 0.002416, -1.21e-5, 0, 0)
        ),
        "ankle_sagittal": Inertial(
            3.1334,
            (0.010136, -0.000799, -0.0669),
            (0.007764, 0.014592, 0.013164, -5.24e-4, -1.425e-3, 1.74e-4),
        ),
    },
}

TRUNK_LINKS: dict[str, Inertial] = {
    "root_waist": Inertial(
        2.5, (-0.010985, -0.000323, 0.033148), (0.038531, 0.017354, 0.053232, 0, 2.38e-4, 0)
    ),
    "trunk_axial": Inertial(
        1.0,
        (-0.002235, -0.000979, -0.018814),
        (0.001978, 0.000900, 0.001472, 2.1e-6, 2.97e-5, -3.1e-6),
    ),
    "trunk_frontal": Inertial(
        14.23545,
        (0.032985, -0.007876, 0.220667),
        (0.335665, 0.126532, 0.263359, 1.62e-4, 0.011858, 9.14e-4),
    ),
}
"""Root waist (pelvis, at the root), axial waist and frontal waist (both at l0 above it)."""

HEAD_LINKS: dict[str, tuple[float, Inertial]] = {
    "neck_axial": (
        0.6282,
        Inertial(1.0, (0.000302, 0.000193, -0.0452), (0.000939, 0.000939, 0.000528, 0, 0, 0)),
    ),
    "neck_frontal": (
        0.6607,
        Inertial(
            2.0, (-0.002729, -0.000086, 0.067027), (0.007599, 0.008325, 0.011403, 0, 6.58e-5, 0)
        ),
    ),
}
"""Neck links: (frame height above the root [m], inertial). Held fixed."""

ARM = Inertial(6.80149, (-0.0023, -0.0764, -0.247), (0.442, 0.439, 0.0088, 0, 0, -0.013))
"""One (right) arm lumped from its six links, CoM from the frontal-shoulder joint; the left
arm mirrors y (and Iyz). Arms are held fixed."""
