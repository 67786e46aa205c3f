"""A bad robot file gets one line per problem, each naming its key and the valid choices.

The robot files are the test biped's (``robot_yaml``: written by ``robot init`` from its MJCF
and from its URDF) with values broken; every check runs (layout, the model's names, the
``package://`` packages, the truth) and one error carries every problem, which the CLI
prints one ``zmpkit: error:`` line each (exit 2). A problem that leaves nothing to check
against (no model file) stops the checks there.
"""

from __future__ import annotations

import pickle
from pathlib import Path
from typing import Any

import pytest
import yaml

from helpers.biped import BIPED_URDF
from zmpkit.cli import main
from zmpkit.errors import InputFileError, InputFileProblemsError
from zmpkit.robots.registry import get_robot
from zmpkit.robots.robot_file_reader import read_robot_file

LEG_JOINTS = "r_hip_roll, r_hip_pitch, r_knee, r_ankle_pitch, r_ankle_roll and 5 more"
"""The biped's ten hinge joints as a message lists them (``_validate.list_some``)."""


def _broken(robot_yaml: Path, changes: dict[str, Any], name: str = "bad.yaml") -> Path:
    """The robot file with ``changes`` (top-level key → value; None deletes the key)."""
    doc = yaml.safe_load(robot_yaml.read_text(encoding="utf-8"))
    for key, value in changes.items():
        if value is None:
            del doc[key]
        else:
            doc[key] = value
    path = robot_yaml.with_name(name)
    path.write_text(yaml.safe_dump(doc, sort_keys=False), encoding="utf-8")
    return path


def _three_problems(robot_yaml: Path) -> Path:
    """An unknown foot body, an unknown leg joint and a negative sole length."""
    legs = yaml.safe_load(robot_yaml.read_text(encoding="utf-8"))["legs"]
    legs["right"][2] = "r_kne"
    feet = {"right": "r_fot", "left": "l_foot"}
    return _broken(robot_yaml, {"feet": feet, "legs": legs, "sole": {"length": -0.14}})


def _problems(path: Path) -> tuple[InputFileError, ...]:
    with pytest.raises(InputFileProblemsError) as caught:
        get_robot(path)
    return caught.value.problems


def test_three_problems_are_three_lines_of_the_cli(
    robot_yaml: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = _three_problems(robot_yaml)
    assert main(["robot", "check", str(bad)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    sole, foot, leg = err.splitlines()
    assert sole == f"zmpkit: error: {bad}: sole.length: expected a number > 0, got -0.14"
    assert foot.startswith(f"zmpkit: error: {bad}: feet.right: unknown body 'r_fot'; bodies: ")
    assert "pelvis" in foot
    assert foot.endswith(" more")  # the bodies listed, shortened
    assert leg == (
        f"zmpkit: error: {bad}: legs.right: unknown joint 'r_kne'; hinge joints: {LEG_JOINTS}"
    )


def test_three_problems_are_the_errors_list(robot_yaml: Path) -> None:
    bad = _three_problems(robot_yaml)
    with pytest.raises(InputFileProblemsError) as caught:
        get_robot(bad)
    error = caught.value
    assert [p.key for p in error.problems] == ["sole.length", "feet.right", "legs.right"]
    assert {p.path for p in error.problems} == {str(bad)}
    assert str(error).splitlines() == [str(p) for p in error.problems]
    assert "bodies: pelvis" in error.problems[1].detail
    assert error.problems[2].detail == f"unknown joint 'r_kne'; hinge joints: {LEG_JOINTS}"
    assert isinstance(error, InputFileError)  # callers catching the one-problem error still do
    assert error.key == "sole.length"  # the first problem's


def test_every_command_with_a_robot_option_prints_every_problem(
    robot_yaml: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bad = _three_problems(robot_yaml)
    out = robot_yaml.parent / "push"
    argv = ["sim", "push", "--robot", str(bad), "--targets", "0,0.02", "--out", str(out)]
    assert main(argv) == 2
    lines = capsys.readouterr().err.splitlines()
    assert [line.split(": ")[3] for line in lines] == ["sole.length", "feet.right", "legs.right"]
    assert not out.exists()


def test_a_missing_model_stops_the_checks_before_the_names(robot_yaml: Path) -> None:
    """Without the model no name can be checked: the unknown foot is not reported."""
    bad = _broken(
        robot_yaml,
        {
            "model": "nope.xml",
            "feet": {"right": "r_fot", "left": "l_foot"},
            "timestep": 0,
        },
    )
    model, timestep = _problems(bad)
    assert (model.key, timestep.key) == ("model", "timestep")
    assert model.detail == f"no such file {bad.parent / 'nope.xml'}"
    assert timestep.detail == "expected a number > 0, got 0"


def test_every_problem_of_the_layout_is_a_line(robot_yaml: Path) -> None:
    """Unknown, missing and mistyped keys, each with what is valid; no model names checked."""
    bad = _broken(
        robot_yaml,
        {
            "colour": "red",
            "feet": {"right": "r_foot", "lft": "l_foot"},
            "legs": None,
            "sole": {"lenght": 0.1},
            "servo": {"kp": 100.0, "kx": 1.0},
            "walking": {"speed": "fast", "stride": 0.1},
        },
    )
    with pytest.raises(InputFileProblemsError) as caught:
        read_robot_file(bad)
    details = {p.key: p.detail for p in caught.value.problems}
    assert details == {
        "colour": "unknown field; valid: name, model, packages, feet, legs, imu, torso, forward, "
        "sole, servo, contact_threshold_n, timestep, truth, walking",
        "feet.lft": "unknown side; valid: right, left",
        "feet.left": "missing; expected a mapping with keys right and left",
        "legs": "missing; expected a mapping with keys right and left",
        "sole.lenght": "unknown key; valid: length, width, height",
        "servo.kx": "unknown gain; valid: kp, ki, kd",
        "walking.stride": "unknown key; valid: com_height, crouch, posture, torso_pitch, "
        "zmp_forward, foot_separation, "
        "max_step_length, control_period, speed, servo_stiffness, servo_damping, "
        "observer_com_noise, observer_zmp_noise",
        "walking.speed": "expected a number > 0, got 'fast'",
    }


def test_every_unknown_name_is_a_line_naming_the_valid_ones(robot_yaml: Path) -> None:
    bad = _broken(
        robot_yaml,
        {
            "feet": {"right": "r_foot", "left": {"site": "l_toe"}},
            "imu": "head",
            "torso": "chest",
            "walking": {"posture": {"r_knee": 0.6, "neck": 0.1}},
        },
    )
    details = {p.key: p.detail for p in _problems(bad)}
    assert list(details) == ["feet.left", "imu", "torso", "walking.posture"]
    assert details["feet.left"].startswith("unknown site 'l_toe'; sites: ")
    assert details["imu"].startswith("unknown body 'head'; bodies: pelvis, ")
    assert details["torso"].startswith("unknown body 'chest'; bodies: pelvis, ")
    assert details["walking.posture"] == (
        "unknown leg joint 'neck'; leg joints: r_hip_roll, r_hip_pitch, r_knee, "
        "r_ankle_pitch, r_ankle_roll and 5 more"
    )


_TRUTH = """
servo_rate_hz: 1000.0
motor: {gear_ratio: 200.0, supply_voltage: 24.0, torque_constant: 0.02, resistance: 1.0,
        inductance: 1.0e-4, rotor_inertia: 1.0e-6}
pid: {kp: 400.0, ki: 200.0, kd: 4.0, integral_limit_link: 0.05}
friction: {coulomb_link: 0.05}
gear: {stiffness: 3000.0, damping: 1.0, backlash: 0.002, inertia_link: 1.0e-3}
flex:
  - {name: r_shank_flex, body: r_shin, axis: [0, 1, 0], stiffness: [4000.0, 0.0, 0.0]}
"""


def test_the_truths_flexible_links_are_checked_with_the_names(robot_yaml: Path) -> None:
    truth = robot_yaml.with_name("truth.yaml")
    truth.write_text(_TRUTH, encoding="utf-8")
    bad = _broken(robot_yaml, {"truth": "truth.yaml", "imu": "head"})
    imu, flex = _problems(bad)
    assert (imu.path, imu.key) == (str(bad), "imu")
    assert (flex.path, flex.key) == (str(truth), "flex[0].body")
    assert flex.detail.startswith("unknown body 'r_shin'; bodies: pelvis, ")


def test_every_unknown_package_is_a_line(tmp_path: Path) -> None:
    """Two feet meshes in two packages found nowhere: two lines; no names checked after."""
    box = '<box size="0.14 0.08 0.02"/>'
    urdf = BIPED_URDF.replace(box, '<mesh filename="package://right_pkg/foot.stl"/>', 1)
    urdf = urdf.replace(box, '<mesh filename="package://left_pkg/foot.stl"/>', 1)
    model = tmp_path / "biped.urdf"
    model.write_text(urdf, encoding="utf-8")
    bad = tmp_path / "robot.yaml"
    bad.write_text(
        "model: biped.urdf\nfeet: {right: r_fot, left: l_foot}\n"
        "legs: {right: [r_knee], left: [l_knee]}\nsole: {width: -1}\n",
        encoding="utf-8",
    )
    sole, right, left = _problems(bad)
    assert sole.key == "sole.width"
    assert (right.path, left.path) == (str(model), str(model))
    assert right.detail.startswith("package://right_pkg/foot.stl: unknown package 'right_pkg'")
    assert left.detail.startswith("package://left_pkg/foot.stl: unknown package 'left_pkg'")


def test_one_problem_reads_as_before_and_the_group_pickles(robot_yaml: Path) -> None:
    bad = _broken(robot_yaml, {"feet": {"right": "r_fot", "left": "l_foot"}})
    with pytest.raises(InputFileProblemsError) as caught:
        get_robot(bad)
    error = caught.value
    (problem,) = error.problems
    assert str(error) == str(problem) == f"{bad}: feet.right: {problem.detail}"
    copy = pickle.loads(pickle.dumps(error))
    assert [str(p) for p in copy.problems] == [str(problem)]
    assert copy.problems[0].key == "feet.right"
