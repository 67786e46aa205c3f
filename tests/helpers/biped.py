"""A small biped for the tests of a user's robot, written as MJCF and as URDF.

8.4 kg: pelvis 2 kg, torso 3 kg, and per leg hip roll and pitch, knee, ankle pitch and roll
(thigh 0.8 kg, shank 0.6 kg, foot 0.3 kg).
"""

from __future__ import annotations

__all__ = ["BIPED_MASS_KG", "BIPED_MJCF", "BIPED_URDF", "LEG_M", "write_biped_robot"]

LEG_M = 0.22
"""Thigh and shank length of the test biped [m]."""


def _mjcf_leg(p: str, y: float) -> str:
    return f"""
      <body name="{p}_thigh" pos="0 {y} -0.04">
        <joint name="{p}_hip_roll" axis="1 0 0" range="-0.5 0.5"/>
        <joint name="{p}_hip_pitch" axis="0 1 0" range="-1.5 1.5"/>
        <geom type="capsule" fromto="0 0 0 0 0 -{LEG_M}" size="0.03" mass="0.8"/>
        <body name="{p}_shank" pos="0 0 -{LEG_M}">
          <joint name="{p}_knee" axis="0 1 0" range="-0.1 2.2"/>
          <geom type="capsule" fromto="0 0 0 0 0 -{LEG_M}" size="0.025" mass="0.6"/>
          <body name="{p}_foot" pos="0 0 -{LEG_M}">
            <joint name="{p}_ankle_pitch" axis="0 1 0" range="-1 1"/>
            <joint name="{p}_ankle_roll" axis="1 0 0" range="-0.5 0.5"/>
            <geom type="box" pos="0.02 0 -0.04" size="0.07 0.04 0.01" mass="0.3"/>
          </body>
        </body>
      </body>"""


BIPED_MJCF = f"""<mujoco model="biped">
  <compiler angle="radian"/>
  <worldbody>
    <body name="pelvis" pos="0 0 0.55">
      <geom type="box" size="0.06 0.1 0.04" mass="2"/>
      <body name="torso" pos="0 0 0.12"><geom type="box" size="0.06 0.09 0.08" mass="3"/></body>
      {_mjcf_leg("r", -0.06)}{_mjcf_leg("l", 0.06)}
    </body>
  </worldbody>
</mujoco>
"""


def _link(name: str, mass: float, geom: str = "", z: float = 0.0) -> str:
    inertia = 'ixx="2e-3" iyy="2e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"'
    collision = f'<collision><origin xyz="0 0 {z}"/><geometry>{geom}</geometry></collision>'
    return (
        f'<link name="{name}"><inertial><origin xyz="0 0 {z}"/><mass value="{mass}"/>'
        f"<inertia {inertia}/></inertial>{collision if geom else ''}</link>"
    )


def _joint(name: str, parent: str, child: str, xyz: str, axis: str) -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}"/><axis xyz="{axis}"/>'
        '<limit lower="-1.5" upper="2.2" effort="100" velocity="10"/></joint>'
    )


def _urdf_leg(p: str, y: float) -> str:
    down = f"0 0 -{LEG_M}"
    return "".join([
        _link(f"{p}_hip", 0.05), _link(f"{p}_ankle", 0.05),
        _link(f"{p}_thigh", 0.8, f'<cylinder radius="0.03" length="{LEG_M}"/>', -LEG_M / 2),
        _link(f"{p}_shank", 0.6, f'<cylinder radius="0.025" length="{LEG_M}"/>', -LEG_M / 2),
        _link(f"{p}_foot", 0.3, '<box size="0.14 0.08 0.02"/>', -0.04),
        _joint(f"{p}_hip_roll", "pelvis", f"{p}_hip", f"0 {y} -0.04", "1 0 0"),
        _joint(f"{p}_hip_pitch", f"{p}_hip", f"{p}_thigh", "0 0 0", "0 1 0"),
        _joint(f"{p}_knee", f"{p}_thigh", f"{p}_shank", down, "0 1 0"),
        _joint(f"{p}_ankle_pitch", f"{p}_shank", f"{p}_ankle", down, "0 1 0"),
        _joint(f"{p}_ankle_roll", f"{p}_ankle", f"{p}_foot", "0 0 0", "1 0 0"),
    ])  # fmt: skip


BIPED_URDF = (
    '<robot name="ubiped">'
    + _link("pelvis", 5.0, '<box size="0.12 0.2 0.08"/>')
    + _urdf_leg("r", -0.06)
    + _urdf_leg("l", 0.06)
    + "</robot>"
)


BIPED_MASS_KG = 2.0 + 3.0 + 2 * (0.8 + 0.6 + 0.3)
"""The biped's mass, without zmpkit's two sole plates [kg]."""


def write_biped_robot(folder, mjcf: str = BIPED_MJCF, model_name: str = "biped.xml"):
    """Write ``mjcf`` into ``folder`` and ``zmpkit robot init`` it; the robot.yaml's path.

    Args:
        folder: a ``pathlib.Path`` (the test's temporary folder).
        mjcf: the model text (default: the biped's; a test's variant of it).
        model_name: the model's file name (``.xml`` or ``.urdf``).
    """
    from zmpkit.cli import main

    model = folder / model_name
    model.write_text(mjcf, encoding="utf-8")
    robot_yaml = folder / "robot.yaml"
    if main(["robot", "init", str(model), "--out", str(robot_yaml)]) != 0:
        raise AssertionError(f"robot init failed on {model}")
    return robot_yaml
