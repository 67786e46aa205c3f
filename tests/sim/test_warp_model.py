"""The fields in which a batch's models differ, found vectorised (no MuJoCo Warp needed).

:func:`~zmpkit.sim.warp_model._differing_fields` reads each model's fields once per dtype
and compares them with the first model's in one operation; it must find exactly what the
per-model, per-field loop it replaced found (``helpers.warp_reference``), raise the same
errors, and :func:`~zmpkit.sim.warp_model.per_world_values` must stack the same arrays.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers.warp_reference import (
    model_arrays,
    reference_differing_fields,
    reference_per_world_values,
)
from zmpkit.errors import ParameterError
from zmpkit.robots.nao import make_nao
from zmpkit.sim.warp_model import _differing_fields, _model_arrays, per_world_values


def _finite(x: float) -> float:
    """``|x|``, with NaN as 0 (for the fields that hold no NaN)."""
    return float(np.nan_to_num(abs(x)))


EDITS = {
    "actuator_gainprm": lambda m, x: m.actuator_gainprm.__setitem__((slice(None), 0), x),
    "tendon_stiffness": lambda m, x: m.tendon_stiffness.__setitem__(slice(None), x),
    "body_mass": lambda m, x: m.body_mass.__setitem__(3, x),
    "dof_damping": lambda m, x: m.dof_damping.__setitem__(7, x),
    "geom_friction": lambda m, x: m.geom_friction.__setitem__((0, 0), x),
    "opt.timestep": lambda m, x: setattr(m.opt, "timestep", 1e-3 * (1 + _finite(x) % 1)),
    "opt.iterations": lambda m, x: setattr(m.opt, "iterations", 1 + int(_finite(x) * 7) % 50),
    "geom_contype": lambda m, x: m.geom_contype.__setitem__(1, int(_finite(x) * 3) % 4),
    "jnt_range": lambda m, x: m.jnt_range.__setitem__((7, 0), x),
}
"""Field edits a batch's candidates may carry; the last three are not all batchable."""


@pytest.fixture(scope="module")
def base() -> mujoco.MjModel:
    """The NAO model with motors, gears and sensors (dcmotors, tendon gears)."""
    return make_nao("M,G,S", None, seed=0).model


def variant(model: mujoco.MjModel, edits: dict[str, float]) -> mujoco.MjModel:
    """A copy of ``model`` with each named field edited to the given value."""
    other = copy.deepcopy(model)
    for name, value in edits.items():
        EDITS[name](other, value)
    return other


def outcome(find, models, batchable) -> tuple[str, ...] | str:
    """The fields found, or the error's message."""
    try:
        return find(models, batchable)
    except ParameterError as exc:
        return f"ParameterError: {exc}"


value = st.one_of(
    st.floats(-5.0, 5.0, allow_nan=False),
    st.sampled_from([0.0, -0.0, float("nan"), 1.0]),
)
batch_edits = st.lists(
    st.dictionaries(st.sampled_from(sorted(EDITS)), value, max_size=3), min_size=0, max_size=5
)


@settings(max_examples=60, deadline=None)
@given(edits=batch_edits, batch_all=st.booleans())
def test_same_fields_and_errors_as_the_per_model_loop(base, edits, batch_all) -> None:
    """Random batches (NaN, signed zeros, zeros in switch fields, unbatchable fields)."""
    models = [base, *(variant(base, e) for e in edits)]
    names = set(model_arrays(base))
    batchable = names if batch_all else names - {"opt.iterations", "geom_contype", "jnt_range"}
    new = outcome(_differing_fields, models, batchable)
    assert new == outcome(reference_differing_fields, models, batchable)
    if isinstance(new, tuple):
        np.testing.assert_equal(
            per_world_values(models, new), reference_per_world_values(models, new)
        )


def test_finds_each_kind_of_field(base) -> None:
    models = [base, variant(base, {"body_mass": 9.0, "opt.timestep": 0.5})]
    models.append(variant(base, {"tendon_stiffness": 2.0, "geom_contype": 3.0}))
    found = _differing_fields(models, set(_model_arrays(base)))
    assert found == ("body_mass", "geom_contype", "opt.timestep", "tendon_stiffness")
    stacked = per_world_values(models, found)
    assert stacked["opt.timestep"].shape == (3,)
    assert stacked["body_mass"].shape == (3, base.nbody)
    assert stacked["body_mass"][1, 3] == 9.0


def test_nan_equals_nan_and_signed_zeros_are_equal(base) -> None:
    nan = variant(base, {"body_mass": float("nan")})
    assert _differing_fields([nan, copy.deepcopy(nan)], set()) == ()
    zero, minus_zero = variant(base, {"body_mass": 0.0}), variant(base, {"body_mass": -0.0})
    assert _differing_fields([zero, minus_zero], set()) == ()


def test_zero_pattern_names_the_field(base) -> None:
    models = [base, variant(base, {"tendon_stiffness": 0.0})]
    with pytest.raises(ParameterError, match=r"which entries of 'tendon_stiffness' are zero"):
        _differing_fields(models, set(_model_arrays(base)))


def test_models_of_different_mjcf_name_the_first_field(base) -> None:
    other = make_nao("M,I,G,F,S", None, seed=0).model
    models = [base, copy.deepcopy(base), other]
    expected = outcome(reference_differing_fields, models, set())
    assert expected.startswith("ParameterError: models[2] differs from models[0] in the size")
    assert outcome(_differing_fields, models, set()) == expected


def test_one_model_differs_in_nothing(base) -> None:
    assert _differing_fields([base], set()) == ()
