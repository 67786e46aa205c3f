"""The columns a MuJoCo Warp rollout keeps and its qpos error sum's layout (no Warp needed)."""

from __future__ import annotations

import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.robots.nao import make_nao
from zmpkit.sim.warp_columns import QposSquareError, check_square_error, record_columns


@pytest.fixture(scope="module")
def model():
    return make_nao("M,G,S", None, seed=0).model


def test_every_column_unless_asked(model) -> None:
    kept = record_columns(model, ("qpos", "sensordata", "site_xmat", "state"), {"qpos": [2, 0]})
    assert kept["qpos"] == (2, 0)  # in the order asked
    assert kept["sensordata"] == tuple(range(model.nsensordata))
    assert kept["site_xmat"] == tuple(range(model.nsite))  # sites, 9 values each
    assert len(kept["state"]) > model.nq + model.nv


@pytest.mark.parametrize(
    ("columns", "message"),
    [
        ({"qvel": [0]}, r"columns names \['qvel'\], which are not recorded"),
        ({"state": [0]}, r"columns names \['state'\].*'state', which keeps every column"),
        ({"qpos": []}, r"columns\['qpos'\] must be a non-empty list of columns in \[0, "),
        ({"qpos": [-1]}, r"columns\['qpos'\] must be a non-empty list"),
        ({"site_xpos": [10_000]}, r"columns\['site_xpos'\] must be a non-empty list"),
    ],
)
def test_bad_columns_are_named(model, columns, message) -> None:
    with pytest.raises(ParameterError, match=message):
        record_columns(model, ("state", "qpos", "site_xpos"), columns)


def square_error(steps_of_groups, j: int = 2) -> QposSquareError:
    targets = tuple(np.ones((len(s), j)) * (g + 1) for g, s in enumerate(steps_of_groups))
    return QposSquareError(
        (7, 8)[:j], tuple(np.asarray(s) for s in steps_of_groups), targets, (0.0,) * j
    )


def test_target_rows_by_step_and_group() -> None:
    se = square_error([[2, 5], [1, 3, 4]])
    table = se.row_of_step(6)
    np.testing.assert_array_equal(table[0], [-1, 0, -1, -1, 1, -1])  # step 1 is column 0
    np.testing.assert_array_equal(table[1], [0, -1, 1, 2, -1, -1])
    padded = se.padded_targets()
    assert padded.shape == (2, 3, 2)
    np.testing.assert_array_equal(padded[0], [[1, 1], [1, 1], [0, 0]])  # zero past its rows
    np.testing.assert_array_equal(padded[1], 2.0)


@pytest.mark.parametrize(
    ("se", "ngroup", "message"),
    [
        (square_error([[2, 5]]), 2, r"for each of the 2 control groups, got 1 and 1"),
        (square_error([[2, 7]]), 1, r"steps must increase within \[1, nstep=6\]"),
        (square_error([[3, 2]]), 1, r"steps must increase"),
        (square_error([[0]]), 1, r"steps must increase"),
        (QposSquareError((7,), (np.array([1]),), (np.zeros((1, 1)),), ()), 1, r"one quantum"),
        (QposSquareError((999,), (np.array([1]),), (np.zeros((1, 1)),), (0.0,)), 1, r"\[0, nq="),
    ],
)
def test_bad_square_errors_are_named(model, se, ngroup, message) -> None:
    with pytest.raises(ParameterError, match=message):
        check_square_error(se, model, ngroup, 6)


def test_no_square_error_is_fine(model) -> None:
    assert check_square_error(None, model, 1, 6) is None
