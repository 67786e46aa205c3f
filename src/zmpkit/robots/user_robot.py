"""A :class:`~zmpkit.robots.robot.Robot` from a user's ``robot.yaml`` and MJCF or URDF.

The simulator's description comes from :func:`~zmpkit.robots.user_model.user_model`; its
truth is what the file gives: the ideal servo's gains and sensor errors at their defaults,
and the effects M, I, G and F only when it names a servo truth file (``truth:``); without one
they are refused rather than silently left out. The balance model
(:mod:`~zmpkit.robots.user_balance`) and the walking defaults
(:mod:`~zmpkit.robots.user_walking`) are derived from the model; with a servo truth file,
so is its fit catalogue (:mod:`~zmpkit.robots.servo_fit`).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco

from zmpkit.errors import ParameterError
from zmpkit.robots.problems import Problems
from zmpkit.robots.robot import FitSpec, Robot, TruthSpec
from zmpkit.robots.robot_file import SIDES, RobotFile
from zmpkit.robots.robot_file_problems import robot_file_problems
from zmpkit.robots.robot_file_reader import draft_robot_file
from zmpkit.robots.servo_fields import SERVO_FIELD_RULE
from zmpkit.robots.servo_fit import SERVO_QUICK_PARAMETERS, servo_fit_catalogue
from zmpkit.robots.servo_truth import (
    ServoTruth,
    apply_servo_effects,
    read_servo_truth,
    servo_truth_from_doc,
)
from zmpkit.robots.user_balance import user_balance
from zmpkit.robots.user_model import UserModel, user_model
from zmpkit.robots.user_walking import user_walking
from zmpkit.sim.description import FootSensor, RobotDescription
from zmpkit.sim.drive import IdealServoParams
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.names import ft_site
from zmpkit.sim.sensor_errors import SensorParams
from zmpkit.sim.servo import ServoLimits
from zmpkit.sim.truth_file import read_truth_file

if TYPE_CHECKING:
    from zmpkit.io.feet import FootMountEntry

__all__ = ["CONTACT_WEIGHT_FRACTION", "UserTruth", "build_user_robot", "load_robot_file"]

CONTACT_WEIGHT_FRACTION = 0.05
"""Default contact threshold of a user's robot: this share of its weight [-]."""
USER_SERVO_LIMITS = ServoLimits(max_velocity=6.0, max_acceleration=200.0)
"""Setpoint limits of a user's robot's servos [rad/s, rad/s²] (typical hobby/kid-size servos)."""


@dataclass(frozen=True)
class UserTruth:
    """The hidden parameters of a user's robot: the servo and the sensor errors.

    Attributes:
        servo: the ideal servo of every leg joint.
        sensors: sensor errors (used with the S effect); default for a user's robot: the
            default errors scaled by its weight (:func:`scaled_sensor_params`).
        source: the robot file.
    """

    servo: IdealServoParams
    sensors: SensorParams = field(default_factory=SensorParams)
    source: str = ""


SENSOR_REFERENCE_WEIGHT_N = 600.0
"""The default sensor errors (:class:`~zmpkit.sim.sensor_errors.SensorParams`) are sized for a
robot of this weight (an 8 N F_z offset is 1.3 % of it); a user's robot gets them scaled by
its weight over this [N]."""


def scaled_sensor_params(mass_kg: float) -> SensorParams:
    """The default F-T errors scaled to a robot of ``mass_kg`` [kg] (forces and moments)."""
    ratio = mass_kg * 9.81 / SENSOR_REFERENCE_WEIGHT_N
    base = SensorParams()
    return replace(
        base,
        ft_offset=tuple(ratio * v for v in base.ft_offset),
        ft_noise_std=tuple(ratio * v for v in base.ft_noise_std),
        ft_quantisation=tuple(ratio * v for v in base.ft_quantisation),
    )


def _check_effects(name: str, effects: EffectSet | str) -> EffectSet:
    on = EffectSet.parse(effects)
    missing = [
        x
        for x, flag in zip("MIGF", (on.motor, on.inductance, on.gear, on.flex), strict=True)
        if flag
    ]
    if missing and effects != "all":
        raise ParameterError(
            f"robot {name!r} has no truth values for effects {', '.join(missing)}; give none or S"
        )
    return EffectSet.parse("S" if on.sensors else "none")


def _feet_mounts(mjcf: str, height: float) -> dict[str, FootMountEntry]:
    model = mujoco.MjModel.from_xml_string(mjcf)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return {
        side: {
            "position": [float(v) for v in data.site(ft_site(side)).xpos],
            "rpy": [0.0, 0.0, 0.0],
            "sole_height": height,
        }
        for side in SIDES
    }


def _description(
    file: RobotFile, built: UserModel, servo: TruthSpec | None
) -> Any:  # the Robot's ``describe``
    mass = built.mass_kg

    def describe(effects: EffectSet | str, truth: Any, threshold: float) -> RobotDescription:
        if servo is None:
            on = _check_effects(file.name, effects)
            sensors = truth.sensors if isinstance(truth, UserTruth) else scaled_sensor_params(mass)
            mjcf = built.mjcf
        else:
            on = EffectSet.parse(effects)
            values: ServoTruth = servo.resolve(truth)
            sensors = values.sensors or scaled_sensor_params(mass)
            mjcf = apply_servo_effects(built.mjcf, file.leg_joints, on, values)
        return RobotDescription(
            name=file.name,
            mjcf=mjcf,
            driven_joints=file.leg_joints,
            feet=tuple(FootSensor.named(side, file.sole_height_m) for side in SIDES),
            effects=on,
            servo_limits=USER_SERVO_LIMITS,
            sensor_params=sensors,
            contact_force_threshold_n=threshold,
        )

    return describe


def _servo_fit(path: Path) -> FitSpec | None:
    """The fit catalogue derived from a servo truth file (:mod:`~zmpkit.robots.servo_fit`).

    The fit replays balance steps: every robot file has a balance model, and a step needs
    no walk that stands.
    """
    catalogue = read_truth_file(path, lambda doc, _: servo_fit_catalogue(doc))
    if not catalogue:
        return None
    names = {p.name for p in catalogue}
    quick = tuple(n for n in SERVO_QUICK_PARAMETERS if n in names) or (catalogue[0].name,)
    return FitSpec(catalogue, quick, "step", SERVO_FIELD_RULE)


def _servo_truth_spec(path: Path) -> TruthSpec:
    def load(other: str | Path | None) -> ServoTruth:
        return read_servo_truth(path if other is None else other)

    return TruthSpec(path, load, servo_truth_from_doc, ServoTruth)


def load_robot_file(path: str | Path) -> Robot:
    """The robot a ``robot.yaml`` describes (see :mod:`zmpkit.robots.robot_file`).

    Built anew on each call; :func:`zmpkit.robots.registry.get_robot` keeps one per version
    of the file.

    Every problem of the file is found before one is raised
    (:func:`~zmpkit.robots.robot_file_problems.robot_file_problems`).

    Raises:
        InputFileError: a file that cannot be read as YAML; else an
            :class:`~zmpkit.errors.InputFileProblemsError` carrying every problem, each a
            line naming the file, the field, what was wrong and the valid names.
    """
    draft = draft_robot_file(path)
    Problems(robot_file_problems(draft)).raise_any()
    assert draft.file is not None  # a file without problems is usable
    return build_user_robot(draft.file, truth_path=draft.file.truth)


def build_user_robot(
    file: RobotFile,
    *,
    truth_path: Path | None = None,
    title: str | None = None,
    summary: str | None = None,
    source: str | None = None,
    fit: FitSpec | None = None,
) -> Robot:
    """The robot of a parsed robot file, with the effects M, I, G, F when it has a truth.

    ``truth_path`` is a servo truth YAML (:mod:`~zmpkit.robots.servo_truth`).

    Args:
        file: the parsed robot file.
        truth_path: the servo truth (shipped, or a robot file's ``truth:``), or None (the
            ideal servo only).
        title: the name in reports; default: the file's name.
        summary: the line of ``zmpkit robot list`` (``{mass_kg}`` is replaced by the model's
            mass [kg]); default: the model file and the mass.
        source: what the registry takes to give this robot again; default: the file's path.
        fit: the simulator fit's catalogue, if any.
    """
    built = user_model(file)
    threshold = file.contact_threshold_n or CONTACT_WEIGHT_FRACTION * built.mass_kg * 9.81
    servo = None if truth_path is None else _servo_truth_spec(truth_path)
    if fit is None and truth_path is not None:
        fit = _servo_fit(truth_path)
    mounts = _feet_mounts(built.mjcf, file.sole_height_m)
    return Robot(
        name=file.name,
        title=title or file.name,
        summary=(summary or "user robot from {path} ({model}), {mass_kg:.3g} kg").format(
            path=file.path, model=file.model.name, mass_kg=built.mass_kg
        ),
        source=source or str(file.path),
        describe=_description(file, built, servo),
        driven_joints=file.leg_joints,
        feet_mounts=lambda: copy.deepcopy(mounts),
        truth=servo or _user_truth_spec(file, built),
        servo_limits=USER_SERVO_LIMITS,
        contact_force_threshold_n=threshold,
        balance=user_balance(file, built),
        walking=user_walking(file, built),
        fit=fit,
    )


def _user_truth_spec(file: RobotFile, built: UserModel) -> TruthSpec:
    truth = UserTruth(built.servo, scaled_sensor_params(built.mass_kg), source=str(file.path))

    def load(_: str | Path | None) -> UserTruth:
        return truth

    def from_doc(_: Mapping[str, Any], __: str | Path) -> UserTruth:
        return truth

    return TruthSpec(file.path, load, from_doc, UserTruth)
