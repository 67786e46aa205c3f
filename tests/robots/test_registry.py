"""The robot registry: built-in robots by name, one Robot type, no robot names elsewhere."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import zmpkit
from zmpkit.errors import ParameterError
from zmpkit.robots.nao import NAO_LEG_JOINTS, NAO_WALK_COM_HEIGHT_M
from zmpkit.robots.registry import get_robot, missing_reason, robot_names, robots_that
from zmpkit.robots.teo import TEO_BALANCE_MASS_KG, TEO_COM_HEIGHT_M, TEO_DRIVEN_JOINTS

SRC = Path(zmpkit.__file__).parent
ROBOT_NAME = re.compile(r"(?<![A-Za-z])(teo|nao|op3|TEO|NAO|OP3|Teo|Nao|Op3)(?![a-z])")
"""A built-in robot's name as a word or an identifier part: ``teo``, ``NAO_LEG``, ``NaoTruth``,
``make_teo``, ``/teo/`` — but not inside a longer lowercase word (``stereo``, ``piano``)."""


def test_no_module_outside_robots_names_a_robot() -> None:
    """Rule: no line of any module under src/zmpkit outside src/zmpkit/robots/ (code,
    identifiers, strings, docstrings and comments alike) names TEO, NAO or OP3; pipelines ask
    a Robot from the registry instead."""
    hits = [
        f"{path.relative_to(SRC)}:{n}: {line.strip()}"
        for path in sorted(SRC.rglob("*.py"))
        if "robots" not in path.relative_to(SRC).parts
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1)
        if ROBOT_NAME.search(line)
    ]
    assert hits == []


def test_registry_lists_the_built_in_robots() -> None:
    assert robot_names() == ("nao", "op3", "teo")  # op3 listed with or without its model
    assert robots_that("balance") == ("op3", "teo")
    assert robots_that("walking") == ("nao", "op3")
    assert robots_that("fit") == ("nao", "op3", "teo")


def test_unknown_robot_names_the_valid_ones() -> None:
    with pytest.raises(ParameterError, match=r"robot must be one of nao, op3, teo; got 'asimo'"):
        get_robot("asimo")
    with pytest.raises(ParameterError, match=r"one of op3, teo; got 'nao' \(it has no balance"):
        get_robot("nao", needs="balance")


def test_built_in_robots_carry_their_numbers() -> None:
    teo, nao = get_robot("teo"), get_robot("nao")
    assert teo.require_balance().mass_kg == TEO_BALANCE_MASS_KG
    assert teo.require_balance().com_height_m == TEO_COM_HEIGHT_M
    assert teo.driven_joints == TEO_DRIVEN_JOINTS
    assert nao.require_walking().com_height_m == NAO_WALK_COM_HEIGHT_M
    assert nao.ik_settings.joint_names == NAO_LEG_JOINTS
    assert nao.ik_settings.posture_rad["LKneePitch"] == pytest.approx(0.90)
    assert get_robot(teo) is teo


def test_every_built_in_robot_compiles_and_stands() -> None:
    for name in (n for n in robot_names() if missing_reason(n) is None):
        sim = get_robot(name).make_simulation("none")
        sim.step(50)
        assert sum(sim.ft(f.foot)[2] for f in sim.robot.feet) > 0.0
