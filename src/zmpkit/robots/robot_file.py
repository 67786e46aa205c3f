"""A user's robot: ``robot.yaml`` naming an MJCF or URDF file, its feet, legs and sensors.

Layout (lengths in m; every path relative to the YAML's folder)::

    name: mybiped                    # optional; default: the YAML's folder name
    model: mybiped.xml               # MJCF or URDF (a free joint is added at the root if none)
    packages: {mybiped_description: ../mybiped_description}  # optional: folders of the
                                     # URDF's package:// URIs (default: the nearest folder
                                     # of that name above the model file)
    feet:                            # body names (or {site: NAME}) of the feet
      right: right_foot
      left: left_foot
    legs:                            # each leg's joints, hip to ankle
      right: [r_hip_roll, r_hip_pitch, r_knee, r_ankle_pitch, r_ankle_roll]
      left: [l_hip_roll, l_hip_pitch, l_knee, l_ankle_pitch, l_ankle_roll]
    imu: torso                       # body carrying the IMU (default: the root body)
    torso: torso                     # body kept upright when walking (default: the root body)
    sole: {length: 0.12, width: 0.07, height: 0.005}  # default: the feet's footprint; 5 mm
    servo: {kp: 2000.0, ki: 2000.0, kd: 10.0}         # default: scaled from weight × CoM height
    contact_threshold_n: 2.5         # default: 5 % of the robot's weight [N]
    timestep: 0.001                  # physics step [s]
    truth: truth.yaml                # optional: motors, gears, flex, sensors for the effects
                                     # M, I, G, F (layout: zmpkit.robots.servo_truth); without
                                     # it the robot has the ideal servo only (effects "none")
    walking:                         # every key optional; defaults derived from the model
      com_height: 0.45               # CoM height of the walk [m]; default: the crouch's
      crouch: 0.08                   # the crouch lowers the hips by this share of the leg [-]
      posture: {r_knee: 0.6}         # joint → angle [rad] of the crouch, instead of the IK's
      torso_pitch: 0.4               # the torso's forward lean while walking [rad]; default 0
      zmp_forward: -0.03             # the planned ZMP's place in each sole, ahead of its
                                     # centre [m]; default 0 (`robot init` chooses both for
                                     # a robot whose legs cannot walk upright and centred)
      foot_separation: 0.12          # default: the feet's distance at the initial pose [m]
      max_step_length: 0.15          # default: 0.4 × leg length (hip to sole) [m]
      control_period: 0.01           # motion frame [s]
      speed: 0.1                     # default forward speed of `zmpkit walk` [m/s]; default 0.2
      servo_stiffness: 18.9          # P gain of P-only leg servos at the joint [N·m/rad]: the
                                     # walk adds the planned joint torques / it to its targets
      servo_damping: 0.85            # their velocity damping [N·m·s/rad] (a PWM drive: stall
                                     # torque / no-load speed), inverted too; needs the above
      observer_com_noise: 0.1        # the ZMP/IP observer's σ_c [m]; default 0.03
      observer_zmp_noise: 0.1        # the ZMP/IP observer's σ_p [m]; default 0.03

zmpkit adds a 6-axis F-T sensor under each foot: a thin sole plate ``sole.height`` thick,
the only part of the foot that touches the floor, whose wrench on the foot the sensor at its
top measures (site ``{side}_ft``; ``{side}_sole`` marks the sole centre). Every problem is one
:class:`~zmpkit.errors.InputFileError` line naming the file, the field and the valid names;
every field is checked, and several problems are raised together as one
:class:`~zmpkit.errors.InputFileProblemsError` (:mod:`zmpkit.robots.problems`). This module
holds the layout; :mod:`zmpkit.robots.robot_file_reader` reads a file into it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from zmpkit.errors import InputFileError

__all__ = [
    "FIELDS",
    "FORWARD_AXES",
    "SIDES",
    "WALKING_FIELDS",
    "RobotFile",
    "RobotFileDraft",
    "WalkingOverrides",
]


SIDES: tuple[str, str] = ("right", "left")
"""The feet a robot file names."""
DEFAULT_SOLE_HEIGHT_M = 0.005
"""Thickness of the sole plate zmpkit adds = F-T sensor height above the sole [m]."""
DEFAULT_TIMESTEP_S = 0.001
"""Physics step of a user's robot [s]."""
FORWARD_AXES = ("+x", "-x", "+y", "-y")
"""The model-frame axes a robot may face (``forward:``); zmpkit turns it to face world +x."""
FIELDS = (
    "name",
    "model",
    "packages",
    "feet",
    "legs",
    "imu",
    "torso",
    "forward",
    "sole",
    "servo",
    "contact_threshold_n",
    "timestep",
    "truth",
    "walking",
)
"""The keys of a robot file."""
WALKING_FIELDS = (
    "com_height",
    "crouch",
    "posture",
    "torso_pitch",
    "zmp_forward",
    "foot_separation",
    "max_step_length",
    "control_period",
    "speed",
    "servo_stiffness",
    "servo_damping",
    "observer_com_noise",
    "observer_zmp_noise",
)
"""The keys of ``walking:`` in a robot file."""


@dataclass(frozen=True)
class WalkingOverrides:
    """What a robot file's ``walking:`` gives; None: derived from the model.

    Attributes:
        com_height_m: CoM height of the walk [m].
        crouch: the crouch lowers the hips by this share of the leg length [-].
        posture_rad: joint → crouch angle [rad] (replaces the IK's crouch).
        torso_pitch_rad: the torso's forward lean while walking [rad].
        zmp_forward_m: where the walk plans its ZMP in each sole, ahead of the centre [m].
        foot_separation_m: lateral distance between the foot centres [m].
        max_step_length_m: largest forward step [m].
        control_period_s: motion frame [s].
        speed_mps: the walk's default forward speed [m/s].
        servo_stiffness_nm_per_rad: P gain of the leg servos at the joint [N·m/rad]
            (:attr:`~zmpkit.robots.robot.WalkingDefaults.servo_stiffness_nm_per_rad`).
        servo_damping_nm_s_per_rad: the leg servos' velocity damping [N·m·s/rad]
            (:attr:`~zmpkit.robots.robot.WalkingDefaults.servo_damping_nm_s_per_rad`).
        observer_com_noise_m: the ZMP/IP observer's σ_c [m]
            (:attr:`~zmpkit.robots.robot.WalkingDefaults.observer_com_noise_m`).
        observer_zmp_noise_m: the ZMP/IP observer's σ_p [m].
    """

    com_height_m: float | None = None
    crouch: float | None = None
    posture_rad: Mapping[str, float] | None = None
    torso_pitch_rad: float | None = None
    zmp_forward_m: float | None = None
    foot_separation_m: float | None = None
    max_step_length_m: float | None = None
    control_period_s: float | None = None
    speed_mps: float | None = None
    servo_stiffness_nm_per_rad: float | None = None
    servo_damping_nm_s_per_rad: float | None = None
    observer_com_noise_m: float | None = None
    observer_zmp_noise_m: float | None = None


@dataclass(frozen=True)
class RobotFile:
    """A parsed ``robot.yaml`` (names not yet checked against the model).

    Attributes:
        path: the YAML file.
        name: the robot's name.
        model: the MJCF or URDF file.
        feet: side → (``"body"`` or ``"site"``, name).
        legs: side → the leg's joints, hip to ankle.
        imu: body carrying the IMU, or None for the root body.
        torso: body kept upright when walking, or None for the root body.
        forward: the axis of the model's root frame the robot faces (:data:`FORWARD_AXES`);
            zmpkit turns the model about the vertical so that it faces the world's +x.
        sole_length_m: sole length, or None for the foot's footprint [m].
        sole_width_m: sole width, or None for the foot's footprint [m].
        sole_height_m: sole plate thickness = F-T height above the sole [m].
        servo: ideal-servo gains ``kp``, ``ki``, ``kd`` given (others derived).
        contact_threshold_n: contact threshold, or None for 5 % of the weight [N].
        timestep_s: physics step [s].
        walking: the ``walking:`` values given (others derived from the model).
        truth: the servo truth file for the effects, or None (the ideal servo only).
        packages: package name → folder, for the model's ``package://`` URIs
            (:mod:`zmpkit.robots.package_uris`).
    """

    path: Path
    name: str
    model: Path
    feet: Mapping[str, tuple[str, str]]
    legs: Mapping[str, tuple[str, ...]]
    imu: str | None
    torso: str | None
    sole_length_m: float | None
    sole_width_m: float | None
    sole_height_m: float
    servo: Mapping[str, float]
    contact_threshold_n: float | None
    timestep_s: float
    walking: WalkingOverrides = WalkingOverrides()
    truth: Path | None = None
    packages: Mapping[str, Path] = field(default_factory=dict)
    forward: str = "+x"

    @property
    def leg_joints(self) -> tuple[str, ...]:
        """Both legs' joints, right leg then left leg."""
        return (*self.legs["right"], *self.legs["left"])


SERVO_KEYS = ("kp", "ki", "kd")
"""The ideal servo's gains a robot file may give."""
SOLE_KEYS = ("length", "width", "height")
"""The keys of ``sole:`` in a robot file."""


@dataclass(frozen=True)
class RobotFileDraft:
    """A robot file read as far as it goes: what it gives, and every problem of its layout.

    Attributes:
        file: the robot file's valid values (a wrong foot or leg left out of ``feet`` or
            ``legs``, a wrong optional value at its default), enough to check the names
            against the model; None when the model cannot be loaded (its path, or a package
            folder, is wrong).
        problems: the layout's problems, one line each, in the file's field order.
    """

    file: RobotFile | None
    problems: tuple[InputFileError, ...]
