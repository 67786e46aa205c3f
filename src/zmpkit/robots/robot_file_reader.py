"""Reading a ``robot.yaml`` (layout: :mod:`zmpkit.robots.robot_file`), every problem kept.

:func:`draft_robot_file` reads as far as the file goes and collects one
:class:`~zmpkit.errors.InputFileError` per problem, in the file's field order;
:func:`read_robot_file` raises them together (:mod:`zmpkit.robots.problems`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

from zmpkit._validate import MAX_ECHO_CHARS, shorten
from zmpkit.errors import InputFileError
from zmpkit.io.yaml_file import read_yaml_mapping
from zmpkit.robots.problems import Problems
from zmpkit.robots.robot_file import (
    DEFAULT_SOLE_HEIGHT_M,
    DEFAULT_TIMESTEP_S,
    FIELDS,
    FORWARD_AXES,
    SERVO_KEYS,
    SIDES,
    SOLE_KEYS,
    WALKING_FIELDS,
    RobotFile,
    RobotFileDraft,
    WalkingOverrides,
)

__all__ = ["draft_robot_file", "read_robot_file"]


T = TypeVar("T")


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


def _signed(path: Path, field: str, value: Any, bound: float, unit: str) -> float | None:
    """A number of either sign within ``±bound``, or None when not given."""
    if value is None:
        return None
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or not math.isfinite(value)
        or abs(value) > bound
    ):
        raise _fail(
            path, field, f"expected a number within ±{bound:g} {unit}, got {shorten(value)}"
        )
    return float(value)


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
        torso_pitch_rad=problems.attempt(
            _signed, path, "walking.torso_pitch", given.get("torso_pitch"), 1.0, "rad"
        ),
        zmp_forward_m=problems.attempt(
            _signed, path, "walking.zmp_forward", given.get("zmp_forward"), 0.2, "m"
        ),
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
