"""Every body, site and joint a robot file names exists in its model, or one problem each."""

from __future__ import annotations

import mujoco

from zmpkit._validate import list_some, shorten
from zmpkit.errors import InputFileError
from zmpkit.robots.problems import Problems
from zmpkit.robots.robot_file import RobotFile
from zmpkit.robots.user_feet import foot_geoms
from zmpkit.robots.user_model_file import body_names

__all__ = ["check_names", "name_problems"]


def _hinges(model: mujoco.MjModel) -> list[str]:
    return [
        model.joint(j).name
        for j in range(model.njnt)
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE  # an unnamed free joint is skipped
    ]


def name_problems(robot: RobotFile, model: mujoco.MjModel) -> tuple[InputFileError, ...]:
    """Every body, site and joint the robot file names that the model lacks, one problem each.

    Checks the feet (and that each has a collision geom), the legs' joints (hinges), the IMU
    and torso bodies and the ``walking.posture`` joints (leg joints). A side whose foot or
    leg did not read (:func:`~zmpkit.robots.robot_file_reader.draft_robot_file`) is skipped.

    Returns:
        The problems, each naming the field and listing the valid names (shortened).
    """
    problems = Problems()
    for side in robot.feet:
        problems.attempt(foot_geoms, robot, model, side)
    hinges = _hinges(model)
    for side, joints in robot.legs.items():
        for name in joints:
            if name not in hinges:
                message = (
                    f"unknown joint {shorten(name)}; hinge joints: {list_some(hinges) or 'none'}"
                )
                problems.add(InputFileError(robot.path, message, key=f"legs.{side}"))
    bodies = body_names(model)
    for field in ("imu", "torso"):
        name = getattr(robot, field)
        if name is not None and name not in bodies:
            message = f"unknown body {shorten(name)}; bodies: {list_some(bodies)}"
            problems.add(InputFileError(robot.path, message, key=field))
    legs = [joint for joints in robot.legs.values() for joint in joints]
    for name in robot.walking.posture_rad or {}:
        if name not in legs:
            message = f"unknown leg joint {shorten(name)}; leg joints: {list_some(legs) or 'none'}"
            problems.add(InputFileError(robot.path, message, key="walking.posture"))
    return problems.found


def check_names(robot: RobotFile, model: mujoco.MjModel) -> None:
    """Every joint and body the robot file names exists (:func:`name_problems`).

    Raises:
        InputFileProblemsError: carrying every unknown name.
    """
    Problems(name_problems(robot, model)).raise_any()
