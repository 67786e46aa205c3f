"""Fuzzing robot.yaml: a valid robot file for a small biped with its values and names broken.

Each case replaces one to three values of the file ``zmpkit robot init`` writes (a body or
joint name, the model's path, a number) by odd text, drops a line, or adds an optional section
with odd numbers (sole, servo, walking). Loading must end with a ``ZmpkitError`` of one short
line per problem (several for several broken values), never another exception.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from helpers.biped import BIPED_MJCF
from helpers.fuzz import Census, reader_problems
from helpers.fuzz_inputs import number_text
from zmpkit.robots.user_robot import load_robot_file

TEMPLATE = """name: biped
model: biped.xml
feet:
  right: r_foot
  left: l_foot
legs:
  right: [r_hip_roll, r_hip_pitch, r_knee, r_ankle_pitch, r_ankle_roll]
  left: [l_hip_roll, l_hip_pitch, l_knee, l_ankle_pitch, l_ankle_roll]
imu: pelvis
torso: pelvis
"""
OPTIONAL = (
    "sole: {{length: {0}, width: 0.07, height: 0.005}}\n",
    "servo: {{kp: {0}, ki: 2000.0, kd: 10.0}}\n",
    "contact_threshold_n: {0}\n",
    "timestep: {0}\n",
    "walking: {{com_height: {0}, foot_separation: 0.12}}\n",
)
ODD_NAMES = st.sampled_from(
    ("", "nothing", "r_foot r_foot", "../biped.xml", "{}", "[]", "null", "pelvis\n  x: 1", "1e3")
)
_SETTINGS = {
    "deadline": None,
    "derandomize": True,
    "database": None,
    "suppress_health_check": [HealthCheck.too_slow],
}


@st.composite
def robot_yaml(draw: st.DrawFn) -> str:
    """The template with one to three of its values or lines broken, maybe a section added."""
    text = TEMPLATE
    for _ in range(draw(st.integers(1, 3))):
        tokens = list(re.finditer(r"(?<=: )[^\s\[\]{},]+|(?<=[\[ ,])[a-z_]+(?=[,\]])", text))
        token = tokens[draw(st.integers(0, len(tokens) - 1))]
        junk = draw(st.one_of(ODD_NAMES, number_text()))
        text = text[: token.start()] + junk.replace("\n", " ") + text[token.end() :]
    if draw(st.booleans()):
        lines = text.splitlines(keepends=True)
        del lines[draw(st.integers(0, len(lines) - 1))]
        text = "".join(lines)
    if draw(st.booleans()):
        section = draw(st.sampled_from(OPTIONAL))
        text += section.format(draw(number_text()).replace("\n", " "))
    return text


def _run(examples: int) -> Census:
    census = Census("reader robot file")

    @settings(max_examples=examples, **_SETTINGS)
    @given(robot_yaml())
    def fuzz(text: str) -> None:
        with tempfile.TemporaryDirectory() as tmp:
            root = Path(tmp)
            (root / "biped.xml").write_text(BIPED_MJCF, encoding="utf-8")
            path = root / "robot.yaml"
            path.write_text(text, encoding="utf-8", errors="surrogatepass")
            census.record(reader_problems(lambda: load_robot_file(str(path)), root), text)

    fuzz()
    return census


def test_the_template_loads(tmp_path: Path) -> None:
    (tmp_path / "biped.xml").write_text(BIPED_MJCF, encoding="utf-8")
    (tmp_path / "robot.yaml").write_text(TEMPLATE, encoding="utf-8")
    assert load_robot_file(str(tmp_path / "robot.yaml")).name == "biped"


def test_fuzz_robot_file_fast() -> None:
    census = _run(40)
    assert census.cases >= 40
    assert census.bad == 0, census.summary()


@pytest.mark.slow
def test_fuzz_robot_file_many() -> None:
    census = _run(600)
    assert census.cases >= 600
    assert census.bad == 0, census.summary()
