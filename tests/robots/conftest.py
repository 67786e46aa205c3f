"""Fixtures of the robot tests: the small test biped's robot.yaml, from its MJCF and its URDF."""

from __future__ import annotations

from pathlib import Path

import pytest

from helpers.biped import BIPED_MJCF, BIPED_URDF
from zmpkit.cli import main


@pytest.fixture(params=["mjcf", "urdf"])
def robot_yaml(request: pytest.FixtureRequest, tmp_path: Path) -> Path:
    """``robot init`` on the biped's model (8.4 kg, five joints a leg); the written robot.yaml.

    The model lies beside it (``biped.xml`` or ``biped.urdf``) in ``tmp_path``.
    """
    model = tmp_path / ("biped.xml" if request.param == "mjcf" else "biped.urdf")
    model.write_text(BIPED_MJCF if request.param == "mjcf" else BIPED_URDF, encoding="utf-8")
    out = tmp_path / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    return out
