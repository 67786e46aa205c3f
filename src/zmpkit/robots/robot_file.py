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
:class:`~zmpkit.errors.InputFileProblemsError` (:mod:`zmpkit.robots.problems`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from zmpkit._validate import MAX_ECHO_CHARS, shorten
from zmpkit.errors import InputFileError
from zmpkit.io.yaml_file import read_yaml_mapping
from zmpkit.robots.problems import Problems

__all__ = [
    "FIELDS",
    "FORWARD_AXES",
    "SIDES",
    "WALKING_FIELDS",
    "RobotFile",
    "RobotFileDraft",
    "WalkingOverrides",
    "draft_robot_file",
    "read_robot_file",
]

T = TypeVar("T")

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


def _fail(path: Path, field: str, message: str) -> InputFileError:
    return InputFileError(path, message, key=field)


def _key(key: object) -> str:
    """A key of the user's file as a message shows it (cut if long)."""
    text = str(key)
    return text if len(text) <= MAX_ECHO_CHARS else shorten(text)


def _number(path: Path, field: str, value: Any, default: float | None) -> float | None:
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        raise _fail(path, field, f"expected a number > 0, got {shorten(value)}")
    return float(value)


def _servo_gain(path: Path, key: str, value: Any) -> float:
    number = _number(path, f"servo.{key}", value, None)
    if number is None or not math.isfinite(number):
        raise _fail(path, f"servo.{key}", f"expected a finite number > 0, got {shorten(value)}")
    return number


def _section(
    path: Path, field: str, value: Any, keys: Sequence[str], problems: Problems, noun: str = "key"
) -> Mapping[str, Any]:
    """A mapping section (``sole``, ``servo``, ``walking``); its unknown keys are problems."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        problems.add(_fail(path, field, f"expected a mapping, got {shorten(value)}"))
        return {}
    for key in value:
        if key not in keys:
            message = f"unknown {noun}; valid: {', '.join(keys)}"
            problems.add(_fail(path, f"{field}.{_key(key)}", message))
    return {k: v for k, v in value.items() if k in keys}


def _sole(path: Path, value: Any, problems: Problems) -> tuple[float | None, float | None, float]:
    """``sole:``'s length, width (None: the foot's footprint) and height [m]."""
    sole = _section(path, "sole", value, SOLE_KEYS, problems)
    length, width, height = (
        problems.attempt(_number, path, f"sole.{key}", sole.get(key), None) for key in SOLE_KEYS
    )
    return length, width, height or DEFAULT_SOLE_HEIGHT_M


def _servo(path: Path, value: Any, problems: Problems) -> dict[str, float]:
    """``servo:``'s gains that are valid."""
    servo = _section(path, "servo", value, SERVO_KEYS, problems, noun="gain")
    gains = {key: problems.attempt(_servo_gain, path, key, servo[key]) for key in servo}
    return {key: gain for key, gain in gains.items() if gain is not None}


def _names(path: Path, field: str, value: Any) -> tuple[str, ...]:
    if not isinstance(value, Sequence) or isinstance(value, str) or not value:
        raise _fail(path, field, f"expected a list of joint names, got {shorten(value)}")
    return tuple(str(v) for v in value)


def _forward(path: Path, value: Any) -> str:
    if value is None:
        return "+x"
    if value not in FORWARD_AXES:
        raise _fail(
            path, "forward", f"expected one of {', '.join(FORWARD_AXES)}, got {shorten(value)}"
        )
    return str(value)


def _foot(path: Path, field: str, value: Any) -> tuple[str, str]:
    if isinstance(value, str):
        return ("body", value)
    if isinstance(value, Mapping) and len(value) == 1 and next(iter(value)) in ("body", "site"):
        kind, name = next(iter(value.items()))
        return (str(kind), str(name))
    raise _fail(path, field, f"expected a body name or {{site: NAME}}, got {shorten(value)}")


def _sides(
    path: Path,
    field: str,
    value: Any,
    parse: Callable[[Path, str, Any], T],
    problems: Problems,
) -> dict[str, T]:
    """``field``'s right and left entries that parse; every other entry is a problem."""
    expected = "expected a mapping with keys right and left"
    if value is None:
        problems.add(_fail(path, field, f"missing; {expected}"))
        return {}
    if not isinstance(value, Mapping):
        problems.add(_fail(path, field, f"{expected}, got {shorten(value)}"))
        return {}
    for key in value:
        if key not in SIDES:
            problems.add(_fail(path, f"{field}.{_key(key)}", "unknown side; valid: right, left"))
    parsed = {}
    for side in SIDES:
        if side not in value:
            problems.add(_fail(path, f"{field}.{side}", f"missing; {expected}"))
            continue
        entry = problems.attempt(parse, path, f"{field}.{side}", value[side])
        if entry is not None:
            parsed[side] = entry
    return parsed


def _text(path: Path, field: str, value: Any, what: str = "a body name") -> str | None:
    """A name the file gives (a number is read as its text), or None if not given."""
    if value is None:
        return None
    if isinstance(value, Mapping | list | bool):
        raise _fail(path, field, f"expected {what}, got {shorten(value)}")
    return str(value)


def _model_path(path: Path, doc: Mapping[str, Any]) -> Path:
    if "model" not in doc:
        raise _fail(path, "model", "missing; expected the MJCF or URDF file's path")
    model = doc["model"]
    if not isinstance(model, str):
        raise _fail(path, "model", f"expected the MJCF or URDF file's path, got {shorten(model)}")
    file = (path.parent / model).resolve()
    if not file.is_file():
        raise _fail(path, "model", f"no such file {file}")
    if file.suffix.lower() not in (".xml", ".urdf", ".mjcf"):
        raise _fail(path, "model", f"expected an .xml (MJCF) or .urdf file, got {file.name}")
    return file


def _truth_path(path: Path, value: Any) -> Path | None:
    if value is None:
        return None
    if not isinstance(value, str):
        raise _fail(path, "truth", f"expected the truth YAML's path, got {shorten(value)}")
    file = (path.parent / value).resolve()
    if not file.is_file():
        raise _fail(path, "truth", f"no such file {file}")
    return file


def _package(path: Path, name: str, folder: Any) -> Path:
    if not isinstance(folder, str):
        raise _fail(path, f"packages.{name}", f"expected a folder, got {shorten(folder)}")
    resolved = (path.parent / folder).resolve()
    if not resolved.is_dir():
        raise _fail(path, f"packages.{name}", f"no such folder {resolved}")
    return resolved


def _packages(path: Path, value: Any, problems: Problems) -> dict[str, Path] | None:
    """The package folders; None if any is wrong (the model's meshes cannot be found)."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        problems.add(
            _fail(path, "packages", f"expected package: folder pairs, got {shorten(value)}")
        )
        return None
    folders = {_key(k): problems.attempt(_package, path, _key(k), value[k]) for k in value}
    return None if None in folders.values() else {k: v for k, v in folders.items() if v}


def _posture(path: Path, value: Any) -> Mapping[str, float] | None:
    if value is None:
        return None
    if not isinstance(value, Mapping) or not all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in value.values()
    ):
        raise _fail(
            path, "walking.posture", f"expected joint: angle [rad] pairs, got {shorten(value)}"
        )
    return {str(k): float(v) for k, v in value.items()}


def _walking(path: Path, value: Any, problems: Problems) -> WalkingOverrides:
    given = _section(path, "walking", value, WALKING_FIELDS, problems)

    def number(key: str) -> float | None:
        return problems.attempt(_number, path, f"walking.{key}", given.get(key), None)

    if "servo_damping" in given and "servo_stiffness" not in given:
        problems.add(
            _fail(
                path, "walking.servo_damping", "needs walking.servo_stiffness (the servos' P gain)"
            )
        )
    return WalkingOverrides(
        com_height_m=number("com_height"),
        crouch=number("crouch"),
        posture_rad=problems.attempt(_posture, path, given.get("posture")),
        foot_separation_m=number("foot_separation"),
        max_step_length_m=number("max_step_length"),
        control_period_s=number("control_period"),
        speed_mps=number("speed"),
        servo_stiffness_nm_per_rad=number("servo_stiffness"),
        servo_damping_nm_s_per_rad=number("servo_damping"),
        observer_com_noise_m=number("observer_com_noise"),
        observer_zmp_noise_m=number("observer_zmp_noise"),
    )


def draft_robot_file(path: str | Path, model: Path | None = None) -> RobotFileDraft:
    """Read a ``robot.yaml`` and check its layout, every field, every problem collected.

    Args:
        path: the ``robot.yaml``.
        model: the MJCF or URDF file, replacing the file's ``model`` field (a built-in
            robot's model found in another package).

    Raises:
        InputFileError: the file is missing, is not YAML or not a mapping (nothing else can
            be checked).
    """
    file = Path(path).resolve()
    doc = read_yaml_mapping(file)
    problems = Problems()
    for key in doc:
        if key not in FIELDS:
            problems.add(_fail(file, _key(key), f"unknown field; valid: {', '.join(FIELDS)}"))
    name = problems.attempt(_text, file, "name", doc.get("name"), "a name")
    model_file = model.resolve() if model is not None else problems.attempt(_model_path, file, doc)
    packages = _packages(file, doc.get("packages"), problems)
    feet = _sides(file, "feet", doc.get("feet"), _foot, problems)
    legs = _sides(file, "legs", doc.get("legs"), _names, problems)
    imu = problems.attempt(_text, file, "imu", doc.get("imu"))
    torso = problems.attempt(_text, file, "torso", doc.get("torso"))
    forward = problems.attempt(_forward, file, doc.get("forward"))
    length, width, height = _sole(file, doc.get("sole"), problems)
    servo = _servo(file, doc.get("servo"), problems)
    threshold = problems.attempt(
        _number, file, "contact_threshold_n", doc.get("contact_threshold_n"), None
    )
    timestep = problems.attempt(_number, file, "timestep", doc.get("timestep"), None)
    robot = RobotFile(
        path=file,
        name=name or file.parent.name,
        model=model_file or file,
        feet=feet,
        legs=legs,
        imu=imu,
        torso=torso,
        sole_length_m=length,
        sole_width_m=width,
        sole_height_m=height,
        servo=servo,
        contact_threshold_n=threshold,
        timestep_s=timestep or DEFAULT_TIMESTEP_S,
        walking=_walking(file, doc.get("walking"), problems),
        truth=problems.attempt(_truth_path, file, doc.get("truth")),
        packages=packages or {},
        forward=forward or "+x",
    )
    usable = model_file is not None and packages is not None
    return RobotFileDraft(robot if usable else None, problems.found)


def read_robot_file(path: str | Path, model: Path | None = None) -> RobotFile:
    """Read and check the layout of a ``robot.yaml`` (module docstring).

    Args:
        path: the ``robot.yaml``.
        model: the MJCF or URDF file, replacing the file's ``model`` field (a built-in
            robot's model found in another package).

    Raises:
        InputFileError: naming the file and the field; with several problems, an
            :class:`~zmpkit.errors.InputFileProblemsError` carrying them all, one line each.
    """
    draft = draft_robot_file(path, model)
    Problems(draft.problems).raise_any()
    assert draft.file is not None  # a file without problems is usable
    return draft.file
