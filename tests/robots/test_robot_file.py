"""A user's robot: robot.yaml + their MJCF, ``zmpkit robot init`` and ``robot check``."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from helpers.biped import BIPED_MASS_KG, BIPED_MJCF
from zmpkit.cli import main
from zmpkit.robots.registry import get_robot
from zmpkit.robots.robot_check import check_robot


@pytest.fixture
def biped(tmp_path: Path) -> Path:
    (tmp_path / "model").mkdir()
    path = tmp_path / "model" / "biped.xml"
    path.write_text(BIPED_MJCF, encoding="utf-8")
    return path


def test_init_guesses_feet_and_legs_and_check_stands_it(
    biped: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "robot" / "robot.yaml"
    assert main(["robot", "init", str(biped), "--out", str(out)]) == 0
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["model"] == "../model/biped.xml"
    assert doc["feet"] == {"right": "r_foot", "left": "l_foot"}
    assert doc["legs"]["right"] == ["r_hip_roll", "r_hip_pitch", "r_knee", "r_ankle_pitch",
                                    "r_ankle_roll"]  # fmt: skip
    assert main(["robot", "check", str(out)]) == 0
    assert "F-T vs contact" in capsys.readouterr().out


def test_a_waist_joint_above_both_hips_belongs_to_neither_leg(tmp_path: Path) -> None:
    """Both legs hang from a waist body with a yaw joint (as a G1's or Apollo's do): the legs
    start below it (before: the waist joint was put first in both legs, then MuJoCo refused
    the model with "repeated name 'waist_yaw' in actuator")."""
    legs_start = BIPED_MJCF.index('<body name="r_thigh"')
    legs_end = BIPED_MJCF.rindex("</body>", 0, BIPED_MJCF.rindex("</body>"))
    waisted = (
        BIPED_MJCF[:legs_start]
        + '<body name="waist" pos="0 0 0"><joint name="waist_yaw" axis="0 0 1" range="-1 1"/>'
        + '<geom type="sphere" size="0.01" mass="0.1" contype="0" conaffinity="0"/>'
        + BIPED_MJCF[legs_start:legs_end]
        + "</body>"
        + BIPED_MJCF[legs_end:]
    )
    model = tmp_path / "waisted.xml"
    model.write_text(waisted, encoding="utf-8")
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["legs"]["right"][0] == "r_hip_roll"
    assert doc["legs"]["left"][0] == "l_hip_roll"
    assert all("waist_yaw" not in leg for leg in doc["legs"].values())
    assert main(["robot", "check", str(out)]) == 0


def test_the_three_zmps_of_a_standing_biped_agree(biped: Path, tmp_path: Path) -> None:
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(biped), "--out", str(out)]) == 0
    result = check_robot(get_robot(out))
    assert result.mass_kg == pytest.approx(BIPED_MASS_KG * 1.004, rel=1e-3)
    assert result.ft_vs_contact_m < 1e-3
    assert result.ft_vs_com_m < 1e-3
    assert result.feet["left"][2] == pytest.approx(0.005, abs=2e-4)  # on a 5 mm sole plate


def _urdf_leg(p: str, y: float) -> str:
    def link(name: str, mass: float, geom: str, z: float = 0.0) -> str:
        inertia = 'ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"'
        return (
            f'<link name="{name}"><inertial><origin xyz="0 0 {z}"/><mass value="{mass}"/>'
            f'<inertia {inertia}/></inertial><collision><origin xyz="0 0 {z}"/>'
            f"<geometry>{geom}</geometry></collision></link>"
        )

    def joint(name: str, parent: str, child: str, xyz: str, axis: str) -> str:
        return (
            f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{xyz}"/><axis xyz="{axis}"/>'
            '<limit lower="-1.5" upper="1.5" effort="100" velocity="10"/></joint>'
        )

    return "".join([
        link(f"{p}_hip", 0.1, '<sphere radius="0.01"/>'),
        link(f"{p}_thigh", 0.8, '<cylinder radius="0.03" length="0.22"/>', -0.11),
        link(f"{p}_foot", 0.3, '<box size="0.14 0.08 0.02"/>', -0.04),
        joint(f"{p}_hip_roll", "pelvis", f"{p}_hip", f"0 {y} -0.04", "1 0 0"),
        joint(f"{p}_hip_pitch", f"{p}_hip", f"{p}_thigh", "0 0 0", "0 1 0"),
        joint(f"{p}_ankle_pitch", f"{p}_thigh", f"{p}_foot", "0 0 -0.22", "0 1 0"),
    ])  # fmt: skip


def test_a_urdf_gets_a_free_joint_and_stands(tmp_path: Path) -> None:
    pelvis = (
        '<link name="pelvis"><inertial><mass value="5"/><inertia ixx="0.01" iyy="0.01" '
        'izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry>'
        '<box size="0.12 0.2 0.08"/></geometry></collision></link>'
    )
    urdf = tmp_path / "biped.urdf"
    urdf.write_text(
        f'<robot name="u">{pelvis}{_urdf_leg("r", -0.06)}{_urdf_leg("l", 0.06)}</robot>',
        encoding="utf-8",
    )
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(urdf), "--out", str(out)]) == 0
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["legs"]["left"] == ["l_hip_roll", "l_hip_pitch", "l_ankle_pitch"]
    result = check_robot(get_robot(out))
    assert result.mass_kg == pytest.approx((5.0 + 2 * 1.2) * 1.004, rel=1e-3)
    assert result.ok


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("model", "nope.xml"), "model: no such file"),
        (
            ("feet", {"right": "r_fot", "left": "l_foot"}),
            "feet.right: unknown body 'r_fot'; bodies:",
        ),
        (("legs", {"right": ["r_kne"], "left": ["l_knee"]}), "legs.right: unknown joint 'r_kne'"),
        (("colour", "red"), "colour: unknown field; valid: name, model"),
    ],
)
def test_bad_robot_files_get_one_line_naming_the_valid_names(
    biped: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], change, message: str
) -> None:
    doc = {
        "model": "model/biped.xml",
        "feet": {"right": "r_foot", "left": "l_foot"},
        "legs": {"right": ["r_knee"], "left": ["l_knee"]},
    }
    doc[change[0]] = change[1]
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(doc), encoding="utf-8")
    assert main(["robot", "check", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert len(err.strip().splitlines()) == 1


def test_robot_list_names_the_built_in_robots(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["robot", "list"]) == 0
    names = [line.split(":")[0] for line in capsys.readouterr().out.splitlines()]
    assert names == ["nao", "op3", "teo"]  # op3 listed whether or not its model is installed


def test_unknown_robot_is_exit_2_with_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["balance", "--robot", "atlas", "--out", "unused"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    expected = "robot must be one of op3, teo; got 'atlas' (or a robot.yaml file)"
    assert err == [f"zmpkit: error: {expected}"]


def test_links_overlapping_at_the_initial_pose_do_not_push_each_other_apart(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An imported URDF whose thighs reach 3 cm into the pelvis across the hip links (MuJoCo
    filters only parent and child): zmpkit excludes those pairs, and the robot stands with
    its three ZMPs together (before: 61 mm apart, the overlap pushing the links apart)."""
    from helpers.biped import BIPED_URDF, LEG_M

    thigh = f'<cylinder radius="0.03" length="{LEG_M}"/>'
    longer = f'<cylinder radius="0.03" length="{LEG_M + 0.06}"/>'
    model = tmp_path / "overlap.urdf"
    model.write_text(BIPED_URDF.replace(thigh, longer))
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["robot", "check", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "excluded self-contacts (2 pairs of links touching at the initial pose): " in printed
    assert "l_thigh–pelvis, pelvis–r_thigh" in printed
    assert "self-contacts after standing: 0" in printed
