"""The compliance's start under the measured load and its history: closed forms, MuJoCo's own
integration of one geared link, and the NAO's own gears."""

from __future__ import annotations

import copy
import math

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.robots.registry import get_robot
from zmpkit.sim.description import FootSensor
from zmpkit.simfit.loaded_start import (
    NEAR_BAND,
    compliant_dofs,
    replay_compliance,
    settle_compliance,
)

G = 9.81

_LINK = """
<mujoco>
  <option gravity="0 0 -{g}"/>
  <worldbody>
    <body name="shank" pos="0 0 1">
      <joint name="drive" type="hinge" axis="0 1 0"/>
      <joint name="drive_gear" type="hinge" axis="0 1 0" limited="false"/>
      <geom type="capsule" fromto="0 0 0 {length} 0 0" size="0.01" mass="{mass}"/>
      <body name="foot" pos="{length} 0 0">
        <geom type="sphere" size="0.02" mass="{foot_mass}"/>
        <site name="ft" pos="0 0 -0.05"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="drive_gear" springlength="{low} {high}" stiffness="{stiffness}">
      <joint joint="drive_gear" coef="1"/>
    </fixed>
  </tendon>
  <actuator><position name="drive" joint="drive" kp="100"/></actuator>
</mujoco>
"""


def _link(stiffness: float, backlash: float, mass: float, foot_mass: float, length: float):
    xml = _LINK.format(
        g=G,
        length=length,
        mass=mass,
        foot_mass=foot_mass,
        low=-backlash / 2,
        high=backlash / 2,
        stiffness=stiffness,
    )
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def _closed_form(torque: float, stiffness: float, backlash: float) -> float:
    """The spring's deflection holding ``torque``: past its dead band by torque / k."""
    return torque / stiffness + math.copysign(backlash / 2, torque)


@settings(max_examples=60, deadline=None)
@given(
    angle=st.floats(-1.2, 1.2),
    stiffness=st.floats(200.0, 1e5),
    backlash=st.floats(0.0, 0.01),
    mass=st.floats(0.2, 5.0),
    foot_mass=st.floats(0.0, 1.0),
    length=st.floats(0.1, 0.5),
    force=st.tuples(*[st.floats(-50.0, 50.0)] * 3),
    moment=st.tuples(*[st.floats(-5.0, 5.0)] * 3),
)
def test_a_gear_holds_gravity_and_the_measured_wrench_as_in_closed_form(
    angle, stiffness, backlash, mass, foot_mass, length, force, moment
):
    """One link on a geared hinge, a foot below a sensor: the reading's wrench at its origin.

    The sensor reads what the foot (its weight and the contact) exerts on the link, so the
    gear holds the link's weight and that wrench applied at the sensor's origin:
    Q = ŷ · [(c − a) × m g + (o − a) × F_s + τ_s], deflection Q/k + sign(Q) b/2.
    """
    model, data = _link(stiffness, backlash, mass, foot_mass, length)
    data.qpos[0] = angle
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    site = model.site("ft").id
    rotation = data.site_xmat[site].reshape(3, 3)
    force_world, moment_world = np.array(force), np.array(moment)
    reading = np.concatenate((rotation.T @ force_world, rotation.T @ moment_world))
    anchor = data.xanchor[0]
    link_com = data.xipos[model.body("shank").id]
    weight = np.array([0.0, 0.0, -G * mass])
    torque = (
        np.cross(link_com - anchor, weight)
        + np.cross(data.site_xpos[site] - anchor, force_world)
        + moment_world
    )[1]
    feet = (FootSensor("right", "f", "t", "ft", 0.05),)

    deflection = settle_compliance(model, data, ("drive",), feet, {"right": reading})

    assert deflection.shape == (1,)
    expected = _closed_form(float(torque), stiffness, backlash)
    assert deflection[0] == pytest.approx(expected, rel=1e-9, abs=1e-12)
    assert data.qpos[1] == deflection[0]
    assert data.qpos[0] == angle  # the driven joint is the encoder's, untouched


def test_a_joint_without_a_spring_or_with_a_servo_is_not_compliant():
    model, data = _link(1000.0, 0.0, 1.0, 0.0, 0.3)
    assert [model.joint(j).name for j in compliant_dofs(model, data, ())] == ["drive_gear"]
    assert compliant_dofs(model, data, ("drive_gear",)).size == 0
    free = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body><joint type='hinge'/><geom size='0.1'/></body>"
        "</worldbody></mujoco>"
    )
    assert compliant_dofs(free, mujoco.MjData(free), ()).size == 0


def test_the_nao_standing_on_its_gears_is_started_where_they_really_deflect():
    """A standing NAO (M, G) settled for 1 s: from its true F-T wrenches and its encoders'
    state, the gears that carry load past their dead band are put where the simulation has
    them (read from its hidden state: a test may), to 2 % of their deflection; the others
    somewhere in their dead band, as the simulation has them."""
    robot = get_robot("nao")
    sim = robot.make_simulation("M,G", seed=0)
    sim.command(sim.encoders())
    sim.step(1000)
    model = sim.model
    joints = compliant_dofs(model, sim.data, sim.robot.driven_joints)
    qadr = model.jnt_qposadr[joints]
    true = sim.data.qpos[qadr].copy()
    data = copy.copy(sim.data)
    data.qpos[qadr] = 0.0
    wrenches = {f.foot: sim.ft_true(f.foot) for f in sim.robot.feet}

    estimate = settle_compliance(model, data, sim.robot.driven_joints, sim.robot.feet, wrenches)

    band = np.array(
        [model.tendon_lengthspring[model.tendon(model.joint(j).name).id, 1] for j in joints]
    )
    loaded = np.abs(true) > 1.05 * band
    assert loaded.sum() >= 4
    np.testing.assert_allclose(estimate[loaded], true[loaded], rtol=0.02)
    assert np.all(np.abs(estimate[~loaded]) <= 1.05 * band[~loaded])
    assert np.all(np.abs(estimate - true)[~loaded] <= 2 * band[~loaded])


_FREE_GEAR = """
<mujoco>
  <option timestep="{dt}" integrator="Euler" gravity="0 0 0"/>
  <worldbody>
    <body name="link">
      <joint name="gear" type="hinge" axis="0 1 0" damping="{damping}" armature="{armature}"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="{mass}"/>
    </body>
  </worldbody>
  <tendon>
    <fixed name="gear" springlength="{low} {high}" stiffness="{stiffness}">
      <joint joint="gear" coef="1"/>
    </fixed>
  </tendon>
</mujoco>
"""


def _free_gear(stiffness: float, backlash: float, damping: float, mass: float, armature: float):
    xml = _FREE_GEAR.format(
        dt=0.001,
        damping=damping,
        armature=armature,
        mass=mass,
        low=-backlash / 2,
        high=backlash / 2,
        stiffness=stiffness,
    )
    model = mujoco.MjModel.from_xml_string(xml)
    return model, mujoco.MjData(model)


def _inertia(model, data) -> float:
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    return float(full[0, 0])


@settings(max_examples=40, deadline=None)
@given(
    stiffness=st.floats(300.0, 2e4),
    backlash=st.floats(1e-4, 0.01),
    damping=st.floats(0.05, 5.0),
    mass=st.floats(0.2, 3.0),
    armature=st.floats(0.0, 0.05),
    loads=st.lists(st.floats(-3.0, 3.0), min_size=2, max_size=30),
    rows=st.integers(1, 12),
)
def test_a_gear_near_its_band_is_replayed_as_mujoco_steps_it(
    stiffness, backlash, damping, mass, armature, loads, rows
):
    """One link on a dead-band gear, its load history given: the replay (started at the first
    row's equilibrium, the load linear between rows spaced ``rows`` ticks) ends where MuJoCo's
    Euler integrator, stepping the same link under the same load, puts it. The last load is
    set inside the band, so the gear is replayed, not settled."""
    model, data = _free_gear(stiffness, backlash, damping, mass, armature)
    load = np.array(loads)
    load[0] = math.copysign(max(abs(load[0]), 0.01), load[0])
    load[-1] = 0.25 * stiffness * backlash / 2 * math.tanh(load[-1])  # within NEAR_BAND
    time_s = np.arange(load.size) * rows * 0.001
    inertia = _inertia(model, data)
    joints = compliant_dofs(model, data, ())

    replayed = replay_compliance(
        model, data, joints, time_s, load[:, None], np.full((load.size, 1), inertia)
    )

    reference = mujoco.MjData(model)
    reference.qpos[0] = _closed_form(-load[0], stiffness, backlash)
    for row in range(1, load.size):
        for tick in range(rows):
            share = tick / rows
            reference.qfrc_applied[0] = -((1 - share) * load[row - 1] + share * load[row])
            mujoco.mj_step(model, reference)
    assert replayed[0] == pytest.approx(reference.qpos[0], rel=1e-7, abs=1e-11)
    assert data.qpos[0] == replayed[0]
    assert data.qvel[0] == 0.0  # the replayed speed is not the robot's: started at rest


def test_a_gear_released_from_a_load_stays_on_the_side_it_was_pushed_to():
    """Pushed past one edge of its band and released: the static equilibrium of a zero load
    is anywhere in the band (the bisection picks the lower edge); the replay keeps the gear
    near the upper edge it came from, as the link, damped inside the band, does."""
    stiffness, backlash = 2000.0, 0.004
    model, data = _free_gear(stiffness, backlash, damping=2.0, mass=1.0, armature=0.01)
    load = np.array([-4.0, -4.0, 0.0, 0.0, 0.0])  # the spring pushes back: the gear at +b/2 + 4/k
    time_s = np.array([0.0, 0.2, 0.25, 0.4, 0.5])
    inertia = np.full((load.size, 1), _inertia(model, data))
    joints = compliant_dofs(model, data, ())

    replayed = replay_compliance(model, data, joints, time_s, load[:, None], inertia)

    assert backlash / 4 < replayed[0] <= backlash / 2
    settled = settle_compliance(model, mujoco.MjData(model), (), (), {})
    assert settled[0] == pytest.approx(-backlash / 2, abs=1e-12)


@settings(max_examples=30, deadline=None)
@given(
    stiffness=st.floats(300.0, 2e4),
    backlash=st.floats(0.0, 0.01),
    history=st.lists(st.floats(-20.0, 20.0), min_size=1, max_size=10),
    beyond=st.floats(NEAR_BAND + 0.01, 50.0),
    sign=st.sampled_from([-1.0, 1.0]),
)
def test_a_gear_the_load_holds_past_its_band_is_put_at_its_equilibrium(
    stiffness, backlash, history, beyond, sign
):
    """Whatever the history, a last load whose equilibrium lies beyond NEAR_BAND half-bands
    (any load on a spring without a band) puts the gear at that equilibrium, in closed form."""
    model, data = _free_gear(stiffness, backlash, damping=1.0, mass=1.0, armature=0.0)
    deflection = sign * max(beyond * backlash / 2, 1e-4)
    last = -stiffness * (deflection - math.copysign(backlash / 2, deflection))
    load = np.array([*history, last])
    time_s = np.arange(load.size) * 0.01
    joints = compliant_dofs(model, data, ())

    replayed = replay_compliance(
        model, data, joints, time_s, load[:, None], np.full((load.size, 1), 0.02)
    )

    assert replayed[0] == pytest.approx(_closed_form(-last, stiffness, backlash), rel=1e-9)
