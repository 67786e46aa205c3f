"""Solver settings for a batch: set on a model, validated at the boundary."""

from __future__ import annotations

import pytest

from zmpkit.errors import ParameterError
from zmpkit.robots.nao import make_nao
from zmpkit.sim.solver_settings import SolverSettings


def test_given_options_are_set_and_the_rest_kept() -> None:
    model = make_nao("M,G", None, seed=0).model
    ls_before = model.opt.ls_iterations
    SolverSettings(iterations=4, tolerance=1e-5).apply(model)
    assert (model.opt.iterations, model.opt.tolerance) == (4, 1e-5)
    assert model.opt.ls_iterations == ls_before
    assert SolverSettings(iterations=4, tolerance=1e-5).label == "iterations=4, tolerance=1e-05"
    assert SolverSettings().label == "model default"


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"iterations": 0}, r"iterations must be an integer >= 1 or None, got 0"),
        ({"iterations": 2.0}, r"iterations must be an integer >= 1 or None, got 2.0"),
        ({"ls_iterations": True}, r"ls_iterations must be an integer >= 1 or None, got True"),
        ({"tolerance": -1.0}, r"tolerance must be >= 0 or None, got -1.0"),
        ({"tolerance": float("nan")}, r"tolerance must be >= 0 or None, got nan"),
    ],
)
def test_bad_settings_are_named(options, message) -> None:
    with pytest.raises(ParameterError, match=message):
        SolverSettings(**options)
