"""Each effect of zmpkit.sim shows its signature on a one-joint arm (closed forms)."""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zmpkit.errors import ParameterError
from zmpkit.sim.builder import (
    GEAR_JOINT_SUFFIX,
    add_flex_joint,
    add_gear_compliance,
    add_ideal_servo,
    add_motor,
)
from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.drive import IdealServoParams, MotorParams
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.sensing import FtChannel
from zmpkit.sim.sensor_errors import SensorParams
from zmpkit.sim.servo import ServoLimits, TrajectoryLimiter
from zmpkit.sim.spring import SofteningSpring

G = 9.81
ARM_MASS_KG = 2.0
ARM_LENGTH_M = 0.5
GRAVITY_TORQUE_NM = ARM_MASS_KG * G * ARM_LENGTH_M / 2  # horizontal arm about its hinge
FLEX_ANCHOR_M = 0.1  # the flex hinge sits this far out along the arm


def _arm(gravity: bool = True, joint_range: str | None = None) -> ET.Element:
    """A horizontal arm on a y hinge; gravity pulls it toward positive angles."""
    root = ET.fromstring(
        f"""<mujoco><option timestep="0.001" integrator="implicitfast"
        gravity="0 0 {-G if gravity else 0}"/>
        <worldbody><body name="arm" pos="0 0 1">
        <joint name="j" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 {ARM_LENGTH_M} 0 0" size="0.02" mass="{ARM_MASS_KG}"/>
        </body></worldbody></mujoco>"""
    )
    if joint_range is not None:
        joint = root.find(".//joint")
        assert joint is not None
        joint.set("range", joint_range)
        joint.set("limited", "true")
    return root


def _compile(root: ET.Element) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(ET.tostring(root, encoding="unicode"))
    return model, mujoco.MjData(model)


def _qpos(model: mujoco.MjModel, data: mujoco.MjData, joint: str) -> float:
    return float(data.qpos[model.jnt_qposadr[model.joint(joint).id]])


# --- EffectSet ---------------------------------------------------------------------------


def test_effect_set_parses_all_none_and_letters() -> None:
    assert EffectSet.parse("all") == EffectSet.all()
    assert EffectSet.parse("none") == EffectSet()
    on = EffectSet.parse("m, g,S")
    assert (on.motor, on.inductance, on.gear, on.flex, on.sensors) == (
        True,
        False,
        True,
        False,
        True,
    )
    assert on.letters == "M,G,S"
    assert EffectSet.parse("M,I,G,F,S").letters == "all"


def test_effect_set_error_lists_valid_letters() -> None:
    with pytest.raises(ParameterError, match=r"unknown effect 'X'.*M \(motor.*S \(sensor"):
        EffectSet.parse("M,X")


# --- G: gear stiffness and backlash --------------------------------------------------------


def test_gear_static_deflection_is_torque_over_stiffness() -> None:
    gear = GearParams(stiffness=2000.0, damping=5.0, backlash=0.0)
    root = _arm()
    add_gear_compliance(root, "j", gear)
    add_ideal_servo(root, "j", IdealServoParams())
    model, data = _compile(root)
    for _ in range(3000):
        mujoco.mj_step(model, data)
    deflection = _qpos(model, data, "j" + GEAR_JOINT_SUFFIX)
    expected = GRAVITY_TORQUE_NM / gear.stiffness  # small-angle: arm stays ~horizontal
    assert deflection == pytest.approx(expected, rel=0.02)


def test_backlash_gives_a_dead_band_of_its_width_in_a_slow_sweep() -> None:
    backlash = 0.01
    root = _arm(gravity=False)
    add_gear_compliance(root, "j", GearParams(stiffness=5000.0, damping=0.0, backlash=backlash))
    add_ideal_servo(root, "j", IdealServoParams())
    tendons = root.find("tendon")
    assert tendons is not None
    link = ET.SubElement(tendons, "fixed", {"name": "link_drag", "damping": "5"})
    ET.SubElement(link, "joint", {"joint": "j", "coef": "1"})
    ET.SubElement(link, "joint", {"joint": "j" + GEAR_JOINT_SUFFIX, "coef": "1"})
    model, data = _compile(root)
    amplitude, speed = 0.03, 0.02  # [rad], [rad/s]
    t = np.arange(0.0, 4 * amplitude / speed, model.opt.timestep)
    motor = amplitude * (2 / np.pi) * np.arcsin(np.sin(2 * np.pi * t * speed / (4 * amplitude)))
    link_angle = np.empty_like(t)
    for k, q_ref in enumerate(motor):
        data.ctrl[0] = q_ref
        mujoco.mj_step(model, data)
        link_angle[k] = _qpos(model, data, "j") + _qpos(model, data, "j" + GEAR_JOINT_SUFFIX)
    rising = np.gradient(motor) > 0
    grid = np.linspace(-0.5 * amplitude, 0.5 * amplitude, 11)
    up = np.interp(
        grid,
        motor[rising][np.argsort(motor[rising])],
        link_angle[rising][np.argsort(motor[rising])],
    )
    down_m, down_l = motor[~rising], link_angle[~rising]
    down = np.interp(grid, down_m[np.argsort(down_m)], down_l[np.argsort(down_m)])
    assert np.mean(up - down) == pytest.approx(-backlash, rel=0.2)


# --- F: passive compliant joint -------------------------------------------------------------


def test_flex_joint_static_deflection_matches_its_polynomial_spring() -> None:
    flex = FlexJoint(
        name="flex",
        body="arm",
        axis=(0.0, 1.0, 0.0),
        anchor=(FLEX_ANCHOR_M, 0.0, 0.0),
        stiffness=(500.0, -2.0e4, 2.0e6),
        damping=2.0,
    )
    root = _arm()
    add_flex_joint(root, flex)
    add_ideal_servo(root, "j", IdealServoParams())
    model, data = _compile(root)
    for _ in range(3000):
        mujoco.mj_step(model, data)
    x = _qpos(model, data, "flex")
    lever = ARM_LENGTH_M / 2 - FLEX_ANCHOR_M
    torque = ARM_MASS_KG * G * lever * np.cos(x + _qpos(model, data, "j"))
    assert flex.torque(x) == pytest.approx(torque, rel=0.01)
    assert x > torque / flex.stiffness[0]  # it softened


def test_flex_joint_rejects_a_buckling_spring() -> None:
    with pytest.raises(ParameterError, match="not monotonic"):
        FlexJoint(name="f", body="b", axis=(0, 1, 0), stiffness=(100.0, -1e4, 1.0))


SOFT = SofteningSpring(stiffness=4000.0, softening_torque=0.5, torque_range=4.0, stages=8)


def test_softening_spring_interpolates_its_law_and_softens_monotonically() -> None:
    for j, deflection in enumerate(SOFT.breakpoints):
        assert SOFT.torque(deflection) == pytest.approx(SOFT.torque_range * j / SOFT.stages)
        assert SOFT.law_torque(deflection) == pytest.approx(SOFT.torque(deflection))
    k = SOFT.segment_stiffness
    assert all(a > b > 0.0 for a, b in itertools.pairwise(k))
    assert SOFT.torque(-0.01) == -SOFT.torque(0.01)  # symmetric
    tau = 3.0  # closed form of the law: δ = τ/k0 + τ²/(k0 τ_s)
    assert SOFT.law_deflection(tau) == pytest.approx((tau + tau**2 / 0.5) / 4000.0)


def test_flex_joint_static_deflection_follows_its_softening_spring() -> None:
    flex = FlexJoint(
        name="flex",
        body="arm",
        axis=(0.0, 1.0, 0.0),
        anchor=(FLEX_ANCHOR_M, 0.0, 0.0),
        stiffness=(SOFT.stiffness, 0.0, 0.0),
        damping=2.0,
        softening_torque=SOFT.softening_torque,
        softening_torque_range=SOFT.torque_range,
        softening_stages=SOFT.stages,
    )
    root = _arm()
    add_flex_joint(root, flex)
    add_ideal_servo(root, "j", IdealServoParams())
    model, data = _compile(root)
    assert model.ntendon == SOFT.stages - 1  # native: one dead-band tendon spring per stage
    for _ in range(3000):
        mujoco.mj_step(model, data)
    x = _qpos(model, data, "flex")
    lever = ARM_LENGTH_M / 2 - FLEX_ANCHOR_M
    torque = ARM_MASS_KG * G * lever * np.cos(x + _qpos(model, data, "j"))
    assert flex.torque(x) == pytest.approx(torque, rel=0.01)
    assert x > 2.0 * torque / SOFT.stiffness  # it softened: over twice the rest compliance


def test_softening_flex_joint_rejects_a_polynomial_too() -> None:
    with pytest.raises(ParameterError, match="replaces the polynomial"):
        FlexJoint("f", "b", (0, 1, 0), stiffness=(100.0, 0.0, 1.0), softening_torque=1.0)
    with pytest.raises(ParameterError, match="stages must be an integer >= 1"):
        SofteningSpring(100.0, 1.0, 10.0, stages=0)


# --- M: voltage limit -----------------------------------------------------------------------


def test_voltage_limit_saturates_the_stall_torque() -> None:
    motor = MotorParams(voltage_limit=3.0, gear_ratio=100.0, coulomb_friction_link=0.0)
    root = _arm(gravity=False, joint_range="-0.1 0.1")
    add_motor(root, "j", motor)
    model, data = _compile(root)
    data.ctrl[0] = motor.gear_ratio * 1.0  # far beyond the stop
    for _ in range(1000):
        mujoco.mj_step(model, data)
    torque_link = float(data.actuator_force[0]) * motor.gear_ratio
    assert torque_link == pytest.approx(motor.stall_torque_link, rel=0.01)


def test_motor_holds_position_with_zero_static_error() -> None:
    motor = MotorParams(gear_ratio=100.0, coulomb_friction_link=0.0)
    root = _arm()
    add_motor(root, "j", motor)
    model, data = _compile(root)
    data.ctrl[0] = motor.gear_ratio * 0.1
    for _ in range(5000):
        mujoco.mj_step(model, data)
    assert _qpos(model, data, "j") == pytest.approx(0.1, abs=1e-4)
    assert model.actuator_armature[0] * motor.gear_ratio**2 == pytest.approx(motor.armature_link)


@pytest.mark.parametrize("error_rad", [0.01, 0.2, 2.0])
@pytest.mark.parametrize("speed_rps", [-3.0, 0.0, 1.5, 4.0])
def test_voltage_drive_is_a_voltage_source_below_and_at_the_clamp(
    error_rad: float, speed_rps: float
) -> None:
    """A PWM drive: v = clamp((R / (N K)) kp e), tau = (N K / R)(v - K N w) at every speed (the
    back-EMF counted once: at the clamp the motor's speed-torque line, not half of it)."""
    motor = MotorParams(
        torque_constant=0.007, resistance=7.3, voltage_limit=12.0, gear_ratio=350.0,
        kp_link=19.0, ki_link=0.0, kd_link=0.0, coulomb_friction_link=0.0,
        viscous_friction_motor=0.0, voltage_drive=True,
    )  # fmt: skip
    root = _arm(gravity=False)
    add_motor(root, "j", motor)
    model, data = _compile(root)
    data.qvel[0], data.ctrl[0] = speed_rps, motor.gear_ratio * error_rad
    mujoco.mj_forward(model, data)
    n, k, r, v = motor.gear_ratio, motor.torque_constant, motor.resistance, motor.voltage_limit
    volts = float(np.clip(motor.kp_link * error_rad * r / (n * k), -v, v))
    expected = n * k / r * (volts - k * n * speed_rps)
    assert float(data.qfrc_actuator[0] + data.qfrc_passive[0]) == pytest.approx(expected, rel=1e-6)
    if volts == v:
        line = motor.stall_torque_link - motor.back_emf_damping_link * speed_rps
        assert expected == pytest.approx(line)


# --- servo trajectory -----------------------------------------------------------------------


@settings(max_examples=25, deadline=None)
@given(target=st.floats(-0.5, 0.5), vmax=st.floats(0.05, 1.0), amax=st.floats(0.05, 2.0))
def test_trajectory_respects_limits_and_arrives(target: float, vmax: float, amax: float) -> None:
    dt = 0.001
    limiter = TrajectoryLimiter([0.0], ServoLimits(vmax, amax), dt)
    limiter.set_target([target])
    previous_v, q = 0.0, 0.0
    for _ in range(int((abs(target) / vmax + 2 * vmax / amax + 1.0) / dt)):
        new_q = limiter.tick()[0]
        v = (new_q - q) / dt
        assert abs(v) <= vmax * (1 + 1e-9)
        if new_q != target:  # the arrival tick may snap onto the target
            assert abs(v - previous_v) <= amax * dt * (1 + 1e-9) + 1e-12
        previous_v, q = v, new_q
    assert q == target
    assert not limiter.moving


def test_synchronized_joints_move_in_proportion_and_arrive_together() -> None:
    dt = 0.001
    limiter = TrajectoryLimiter([0.0, 0.1, 0.0], ServoLimits(0.35, 0.5, synchronized=True), dt)
    limiter.set_target([0.2, 0.05, 0.0])
    arrival: dict[int, int] = {}
    for k in range(2000):
        position = limiter.tick()
        assert position[1] - 0.1 == pytest.approx(-0.25 * position[0], abs=1e-12)
        assert position[2] == 0.0
        for i, goal in ((0, 0.2), (1, 0.05)):
            if position[i] == goal:
                arrival.setdefault(i, k)
    assert limiter.position == [0.2, 0.05, 0.0]
    assert arrival[0] == arrival[1]  # the same tick


# --- S: F-T sensor --------------------------------------------------------------------------


def test_ft_offset_and_gain_show_in_a_noise_free_reading() -> None:
    params = SensorParams(
        ft_offset=(1, 2, 3, 0.1, 0.2, 0.3),
        ft_gain_error=0.05,
        ft_noise_std=(0,) * 6,
        ft_quantisation=(0,) * 6,
        ft_cutoff_hz=0.0,
    )
    channel = FtChannel(params, params.ft_offset, np.random.default_rng(0))
    wrench = np.array([10.0, 0.0, 300.0, 1.0, -2.0, 0.0])
    out = channel.sample(wrench)
    np.testing.assert_allclose(out, 1.05 * wrench + np.array(params.ft_offset))


def test_ft_per_axis_gain_and_offset_drift_in_a_noise_free_reading() -> None:
    drift_std = (0.1, 0.1, 0.2, 0.01, 0.01, 0.005)
    params = SensorParams(
        ft_offset=(1, 2, 3, 0.1, 0.2, 0.3),
        ft_noise_std=(0,) * 6,
        ft_quantisation=(0,) * 6,
        ft_cutoff_hz=0.0,
        ft_rate_hz=100.0,
        ft_offset_drift_std=drift_std,
    )
    gains = (0.01, -0.02, 0.03, 0.0, 0.05, -0.01)
    channel = FtChannel(params, params.ft_offset, np.random.default_rng(3), gains)
    rate = np.asarray(drift_std) * np.random.default_rng(3).standard_normal(6)  # its draw
    wrench = np.array([10.0, -4.0, 300.0, 1.0, -2.0, 0.5])
    for k in range(5):
        out = channel.sample(wrench)
        expected = (1.0 + np.asarray(gains)) * wrench + np.asarray(params.ft_offset)
        np.testing.assert_allclose(out, expected + rate * k / 100.0, rtol=1e-12, atol=1e-12)


def test_ft_with_drift_and_gains_batched_is_repeated_sampling() -> None:
    import copy

    from zmpkit.sim.sensing import sample_series

    params = SensorParams(ft_offset_drift_std=(0.1, 0.1, 0.2, 0.01, 0.01, 0.005))
    gains = [(0.01, -0.02, 0.03, 0.0, 0.05, -0.01), (0.0,) * 6]
    channels = [FtChannel(params, params.ft_offset, np.random.default_rng(s), g) for s, g in
                zip((1, 2), gains, strict=True)]  # fmt: skip
    channels[0].sample(np.ones(6))  # one already started
    reference = [copy.deepcopy(c) for c in channels]
    wrenches = 100.0 * np.random.default_rng(0).standard_normal((2, 30, 6))
    expected = np.array(
        [[c.sample(w) for w in ws] for c, ws in zip(reference, wrenches, strict=True)]
    )
    np.testing.assert_array_equal(sample_series(channels, wrenches), expected)


def test_ft_same_seed_same_samples() -> None:
    params = SensorParams()
    a = FtChannel(params, params.ft_offset, np.random.default_rng(7))
    b = FtChannel(params, params.ft_offset, np.random.default_rng(7))
    wrench = np.array([0.0, 0.0, 300.0, 0.0, 1.0, 0.0])
    for _ in range(20):
        np.testing.assert_array_equal(a.sample(wrench), b.sample(wrench))


def test_sensor_params_reject_wrong_shapes() -> None:
    with pytest.raises(ParameterError, match=r"ft_offset must have shape \(6\)"):
        SensorParams(ft_offset=(1.0, 2.0))
