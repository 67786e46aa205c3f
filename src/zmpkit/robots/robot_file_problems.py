"""Every problem of a user's robot file at once: its layout, its model's names, its truth.

The checks run in the order a user fixes them, each collecting all it finds
(:mod:`zmpkit.robots.problems`):

1. the layout (:func:`~zmpkit.robots.robot_file_reader.draft_robot_file`): unknown or missing
   keys, types, numbers, the model's, truth's and package folders' paths;
2. the model loads and compiles (a missing or broken model file, an unknown ``package://``
   package): when it does not, no name can be checked, and the checks stop there;
3. the names (:func:`~zmpkit.robots.user_model_names.name_problems`): feet, legs, IMU, torso,
   ``walking.posture``, each unknown one listing the model's valid names;
4. the truth file (``truth:``): its values (:func:`~zmpkit.robots.servo_truth.read_servo_truth`)
   and the bodies of its flexible links.
"""

from __future__ import annotations

from pathlib import Path

import mujoco

from zmpkit._validate import list_some, shorten
from zmpkit.errors import InputFileError
from zmpkit.robots.problems import Problems
from zmpkit.robots.robot_file import RobotFileDraft
from zmpkit.robots.servo_truth import ServoTruth, read_servo_truth
from zmpkit.robots.user_model_file import body_names, compile_model
from zmpkit.robots.user_model_names import name_problems

__all__ = ["flex_problems", "robot_file_problems"]


def flex_problems(
    truth: ServoTruth, path: Path, model: mujoco.MjModel
) -> tuple[InputFileError, ...]:
    """The truth's flexible links on bodies the model lacks, one problem each.

    Args:
        truth: the servo truth.
        path: its file (named in each problem).
        model: the robot's model.
    """
    bodies = body_names(model)
    return tuple(
        InputFileError(
            path,
            f"unknown body {shorten(flex.body)}; bodies: {list_some(bodies)}",
            key=f"flex[{k}].body",
        )
        for k, flex in enumerate(truth.flex)
        if flex.body not in bodies
    )


def robot_file_problems(draft: RobotFileDraft) -> tuple[InputFileError, ...]:
    """Every problem of a drafted robot file (module docstring), in the order found.

    Args:
        draft: the robot file as read, with its layout's problems.

    Returns:
        The problems, one line each; empty when the robot file is good.
    """
    problems = Problems(draft.problems)
    file = draft.file
    if file is None:  # the model's path or a package folder is wrong: no names to check
        return problems.found
    model = problems.attempt(compile_model, file)
    if model is None:
        return problems.found
    problems.extend(name_problems(file, model))
    if file.truth is not None:
        truth_path = file.truth
        truth = problems.attempt(read_servo_truth, truth_path)
        if truth is not None:
            problems.extend(flex_problems(truth, truth_path, model))
    return problems.found
