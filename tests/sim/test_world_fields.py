"""Per-world model fields: writes into one compiled model, derived fields, Warp's checks.

That the writes of a robot's fit parameters equal each candidate's compiled MJCF is tested
in ``tests/simfit/test_candidate_worlds.py``; here the mechanics, on the virtual NAO.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest

from zmpkit.errors import ParameterError
from zmpkit.robots.registry import get_robot
from zmpkit.sim.effect_fields import mjcf_number
from zmpkit.sim.world_fields import SETCONST_FIELDS, FieldWrite, WorldFields

NAO = get_robot("nao")


@pytest.fixture(scope="module")
def template() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(NAO.description("M,G").mjcf)


def test_a_write_sets_its_entries_per_world_and_a_later_one_wins(
    template: mujoco.MjModel,
) -> None:
    first = FieldWrite.of("tendon_stiffness", [0, 2], np.array([10.0, 20.0, 30.0]))
    later = FieldWrite.of("tendon_stiffness", [2], np.array([[1.0], [2.0], [3.0]]))
    worlds = WorldFields.of_writes(template, [first, later], 3)
    assert worlds.names == ("tendon_stiffness",)
    stiffness = worlds.values["tendon_stiffness"]
    np.testing.assert_array_equal(stiffness[:, 0], [10.0, 20.0, 30.0])
    np.testing.assert_array_equal(stiffness[:, 2], [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(stiffness[:, 1], template.tendon_stiffness[[1, 1, 1]])
    assert template.tendon_stiffness[0] != 10.0  # the template is left unchanged
    model = worlds.model(1)
    np.testing.assert_array_equal(model.tendon_stiffness, stiffness[1])


def test_writes_must_have_one_row_per_world(template: mujoco.MjModel) -> None:
    write = FieldWrite.of("tendon_damping", [0], np.array([1.0, 2.0]))
    with pytest.raises(ParameterError, match="has 2 worlds, expected 3"):
        WorldFields.of_writes(template, [write], 3)


def test_derived_fields_are_mj_setconst_of_each_world(template: mujoco.MjModel) -> None:
    torso = int(template.body("torso").id)
    mass = np.array([template.body_mass[torso], 1.2])
    worlds = WorldFields.of_writes(template, [FieldWrite.of("body_mass", [torso], mass)], 2, True)
    for world in range(2):
        want = copy.copy(template)
        want.body_mass[torso] = mass[world]
        mujoco.mj_setConst(want, mujoco.MjData(want))
        for name in SETCONST_FIELDS:
            np.testing.assert_array_equal(worlds.values[name][world], getattr(want, name))
    np.testing.assert_array_equal(worlds.values["body_subtreemass"][0], template.body_subtreemass)
    assert worlds.values["body_subtreemass"][1, 0] > template.body_subtreemass[0]


def test_mjcf_number_reads_back_what_the_builder_prints() -> None:
    values = np.array([[0.1 + 0.2, 1.0 / 3.0], [2.0e-5 / 7.0, 1.0 / 3.0]])
    want = [[0.3, 0.3333333333], [2.857142857e-06, 0.3333333333]]
    np.testing.assert_array_equal(mjcf_number(values), want)


@pytest.mark.needs_warp
def test_warp_refuses_fields_it_cannot_batch_or_zero_patterns(template: mujoco.MjModel) -> None:
    import mujoco_warp as mjw

    from zmpkit.sim.warp_model import world_fields_for_warp

    types = np.repeat(template.actuator_dyntype[None].astype(np.float64), 2, 0)
    with pytest.raises(ParameterError, match="'actuator_dyntype', which MuJoCo Warp cannot"):
        world_fields_for_warp(mjw, WorldFields(template, {"actuator_dyntype": types}, 2))
    zeroed = np.repeat(template.tendon_stiffness[None], 2, 0)
    zeroed[1, 0] = 0.0
    with pytest.raises(ParameterError, match="which entries of 'tendon_stiffness' are zero"):
        world_fields_for_warp(mjw, WorldFields(template, {"tendon_stiffness": zeroed}, 2))
    unread = {"dof_M0": np.repeat(template.dof_M0[None], 2, 0), "tendon_stiffness": zeroed[:1]}
    kept = world_fields_for_warp(mjw, WorldFields(template, unread, 1))
    assert kept.names == ("tendon_stiffness",)  # dof_M0: never read by MuJoCo Warp
