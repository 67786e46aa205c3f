"""FEET.yaml: parsed mounts and errors that name the field."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from zmpkit.errors import InputFileError
from zmpkit.io import read_feet_yaml


def test_reads_both_feet(feet_yaml: Path) -> None:
    feet = read_feet_yaml(feet_yaml)
    assert set(feet) == {"right", "left"}
    np.testing.assert_allclose(feet["left"].position, [0.0, 0.1285, 0.010])
    np.testing.assert_allclose(feet["right"].rotation, np.diag([1.0, -1.0, -1.0]), atol=1e-12)
    assert feet["right"].sole_height == pytest.approx(0.010)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("right: {position: [0,0,0], rpy: [0,0,0], sole_height: 0.01}\n", "missing foot 'left'"),
        (
            "right: {position: [0,0], rpy: [0,0,0], sole_height: 0.01}\n"
            "left: {position: [0,0,0], rpy: [0,0,0], sole_height: 0.01}\n",
            r"field 'right.position' must be a list of 3 numbers, got \[0, 0\]",
        ),
        (
            "right: {position: [0,0,0], rpy: [0,0,0]}\n"
            "left: {position: [0,0,0], rpy: [0,0,0], sole_height: 0.01}\n",
            "foot 'right' is missing field 'sole_height'",
        ),
        (
            "right: {position: [0,0,0], rpy: [0,x,0], sole_height: 0.01}\n"
            "left: {position: [0,0,0], rpy: [0,0,0], sole_height: 0.01}\n",
            r"field 'right.rpy\[1\]' must be a number, got 'x'",
        ),
        (
            "right: {position: [0,0,0], rpy: [0,0,0], sole_height: -1}\n"
            "left: {position: [0,0,0], rpy: [0,0,0], sole_height: 0.01}\n",
            r"field 'right.sole_height' must be >= 0 m, got -1.0",
        ),
        ("middle: {}\n", "unknown foot 'middle'; valid feet: right, left"),
        ("right: [1, 2\n", r"line \d+: invalid YAML"),
        ("", "expected a mapping at the top level, got an empty file"),
    ],
)
def test_bad_feet_yaml(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "feet.yaml"
    path.write_text(text)
    with pytest.raises(InputFileError, match=message):
        read_feet_yaml(path)
