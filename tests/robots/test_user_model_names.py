"""A user's model goes in unedited: what zmpkit adds is named in its own namespace.

MuJoCo Menagerie's G1 and Apollo define a site ``imu`` of their own; a model may name a geom
``floor`` or a site ``right_sole``. zmpkit's sole plates, F-T and sole sites, IMU site and
floor are named under :data:`zmpkit.sim.names.NAMESPACE`, so such a model compiles and is
checked as it is.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import pytest

from helpers.biped import BIPED_MJCF, write_biped_robot
from zmpkit.cli import main
from zmpkit.robots.registry import get_robot
from zmpkit.sim.names import FLOOR_GEOM, IMU_SITE, NAMESPACE, ft_site, sole_site

# the user's own elements under every name zmpkit used to give its own
THEIRS = (
    '<site name="imu" pos="0 0 0.02"/><site name="right_ft"/><site name="left_sole"/>'
    '<geom name="floor" type="sphere" size="0.01" mass="0.01" contype="0" conaffinity="0"/>'
)


@pytest.fixture
def crowded_robot_yaml(tmp_path: Path) -> Path:
    pelvis = '<geom type="box" size="0.06 0.1 0.04" mass="2"/>'
    return write_biped_robot(tmp_path, BIPED_MJCF.replace(pelvis, pelvis + THEIRS, 1))


def test_a_model_with_zmpkits_old_names_goes_in_unedited(
    crowded_robot_yaml: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["robot", "check", str(crowded_robot_yaml)]) == 0
    assert "F-T vs contact" in capsys.readouterr().out
    robot = get_robot(str(crowded_robot_yaml))
    model = robot.make_simulation("none").model
    for name in ("imu", "right_ft", "left_sole"):  # the user's sites, as they were
        assert model.site(name).bodyid == model.body("pelvis").id
    assert model.geom("floor").type == mujoco.mjtGeom.mjGEOM_SPHERE
    assert model.geom(FLOOR_GEOM).type == mujoco.mjtGeom.mjGEOM_PLANE  # zmpkit's, beside it
    assert model.site(IMU_SITE).bodyid == model.body("pelvis").id
    for side in ("right", "left"):
        assert model.site(ft_site(side)).name.startswith(NAMESPACE)
        assert model.site(sole_site(side)).name.startswith(NAMESPACE)


def test_a_model_whose_defaults_switch_collisions_off_stands_on_zmpkits_plates(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Menagerie's Apollo gives every geom ``contype`` 0 and ``condim`` 1 by default (its
    scene file adds explicit foot-floor pairs): robot init finds the feet among all geoms,
    and zmpkit's floor and sole plates collide, with friction, whatever the defaults say
    (before: "found fewer than two separate lowest bodies (feet)", then a robot that fell
    through the floor)."""
    defaults = '<default><geom contype="0" conaffinity="0" condim="1"/></default>'
    mjcf = BIPED_MJCF.replace('<compiler angle="radian"/>', '<compiler angle="radian"/>' + defaults)
    robot_yaml = write_biped_robot(tmp_path, mjcf)
    capsys.readouterr()
    assert main(["robot", "check", str(robot_yaml)]) == 0
    assert "F-T vs contact" in capsys.readouterr().out
    model = get_robot(str(robot_yaml)).make_simulation("none").model
    for side in ("right", "left"):
        plate = model.geom(f"{NAMESPACE}{side}_sole")
        assert plate.contype == 1
        assert plate.condim == 3
