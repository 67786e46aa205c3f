"""NAO's public URDF (the ``qibullet`` wheel's) through a robot.yaml matches the built-in NAO.

The wheel ships ``qibullet/robot_data/nao.urdf`` without NAO's meshes (qibullet downloads them
after a licence prompt), so the URDF names 78 mesh files that do not exist: the robot-file
loader drops those geoms (:func:`~zmpkit.robots.user_model_file.drop_missing_meshes`) and keeps
the links' ``<inertial>`` masses; each foot keeps its four FSR boxes as collision geoms.

The built-in NAO's design model (its walking IK model) takes its link inertials from the same
public URDF (``robots/nao/geometry.py``), so the two agree to the URDF's rounding once zmpkit's
additions are set apart: the two sole plates under the feet (0.2 % of the weight each) and
the sole plates' height. The built-in *simulated* NAO carries the real torso (5.406 kg, the
CAD-vs-real effect of its truth file), which the URDF, a CAD model, does not.

qibullet is installed without its dependencies (``pip install --no-deps qibullet``, as the
Makefile does): only the URDF file is read, never imported, so pybullet is not needed.
"""

from __future__ import annotations

from importlib.util import find_spec
from pathlib import Path

import mujoco
import numpy as np
import pytest

from zmpkit.robots.registry import get_robot
from zmpkit.sim.names import ft_plate_body, sole_site

SPEC = find_spec("qibullet")  # finds the package without importing it (it imports pybullet)
pytestmark = pytest.mark.skipif(SPEC is None, reason="qibullet is not installed")

LEGS = ("HipYawPitch", "HipRoll", "HipPitch", "KneePitch", "AnklePitch", "AnkleRoll")
URDF_ROBOT_YAML = """\
name: nao_urdf
model: {model}
feet: {{right: r_ankle, left: l_ankle}}
legs:
  right: [{right}]
  left: [{left}]
imu: torso
torso: torso
"""
SIDES = {"left": ("l_ankle", "LShoulderPitch"), "right": ("r_ankle", "RShoulderPitch")}
ARMS_DOWN_RAD = np.pi / 2
"""NAO's ShoulderPitch at which the arms hang, as the built-in NAO's one-body arms do (the
URDF's zero pose holds them forward, horizontal) [rad]."""


@pytest.fixture(scope="module")
def urdf_robot_yaml(tmp_path_factory: pytest.TempPathFactory) -> Path:
    assert SPEC is not None
    assert SPEC.submodule_search_locations
    urdf = Path(next(iter(SPEC.submodule_search_locations))) / "robot_data" / "nao.urdf"
    assert urdf.is_file()
    path = tmp_path_factory.mktemp("nao_urdf") / "robot.yaml"
    text = URDF_ROBOT_YAML.format(
        model=urdf,
        right=", ".join(f"R{j}" for j in LEGS),
        left=", ".join(f"L{j}" for j in LEGS),
    )
    path.write_text(text, encoding="utf-8")
    return path


def _standing(robot_yaml: Path) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The URDF robot as simulated (sole plates, no effects), arms lowered."""
    model = mujoco.MjModel.from_xml_string(get_robot(str(robot_yaml)).description("none").mjcf)
    data = mujoco.MjData(model)
    for _, shoulder in SIDES.values():
        data.qpos[model.jnt_qposadr[model.joint(shoulder).id]] = ARMS_DOWN_RAD
    mujoco.mj_forward(model, data)
    return model, data


def _builtin_design() -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = get_robot("nao").ik_model()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def _plates(model: mujoco.MjModel) -> list[int]:
    return [model.body(ft_plate_body(side)).id for side in SIDES]


def test_the_urdf_nao_weighs_what_the_built_in_nao_weighs(urdf_robot_yaml: Path) -> None:
    """Mass: equal to 0.1 g once zmpkit's sole plates are set apart (the URDF adds 2 mg
    sensor-frame links); with them, 0.4 % more (two plates of 0.2 % each)."""
    model, _ = _standing(urdf_robot_yaml)
    builtin, _ = _builtin_design()
    total, design = float(model.body_subtreemass[0]), float(builtin.body_subtreemass[0])
    plates = float(sum(model.body_mass[b] for b in _plates(model)))
    assert total - plates == pytest.approx(design, abs=1e-4)  # 5.3054 kg vs 5.30535 kg
    assert total == pytest.approx(design * 1.004, rel=1e-4)


def test_the_urdf_nao_stands_with_the_built_in_nao_com_height(urdf_robot_yaml: Path) -> None:
    """CoM height above the ankle axes, arms down: equal to 0.1 mm without zmpkit's sole
    plates; with them (21 g, 5 cm below the ankles) 1.1 mm lower, inside 2 mm. Above the
    floor the URDF robot stands 6 mm higher: the 5 mm sole plate plus half the 2 mm FSR
    boxes that are its feet's collision geoms."""
    model, data = _standing(urdf_robot_yaml)
    _, bdata = _builtin_design()
    plates = _plates(model)
    kept = [b for b in range(1, model.nbody) if b not in plates]
    mass = model.body_mass[kept]
    com_z = float(mass @ data.xipos[kept, 2] / mass.sum())
    ankle = float(data.body("l_ankle").xpos[2])
    builtin_above_ankle = float(bdata.subtree_com[0][2] - bdata.body("LAnkle").xpos[2])
    assert com_z - ankle == pytest.approx(builtin_above_ankle, abs=1e-4)  # 0.2311 m
    with_plates = float(data.subtree_com[0][2]) - ankle
    assert with_plates == pytest.approx(builtin_above_ankle, abs=2e-3)
    sole = float(data.site(sole_site("left")).xpos[2])
    builtin_sole = float(bdata.site(sole_site("left")).xpos[2])
    assert ankle - sole == pytest.approx(
        float(bdata.body("LAnkle").xpos[2]) - builtin_sole + 0.005 + 0.001, abs=1e-6
    )


def test_missing_meshes_are_dropped_and_the_feet_stand_on_their_fsr_boxes(
    urdf_robot_yaml: Path,
) -> None:
    robot = get_robot(str(urdf_robot_yaml))
    model = mujoco.MjModel.from_xml_string(robot.description("none").mjcf)
    assert model.nmesh == 0
    sim = robot.make_simulation("none")
    sim.step(200)
    weight = float(model.body_subtreemass[0]) * 9.81
    assert sim.ft("left")[2] + sim.ft("right")[2] == pytest.approx(weight, rel=0.02)
