r"""Designed double-support experiments: joint targets over time that excite the effects.

A walk excites everything at once, at the step frequency, through contacts that switch; a
fit of every effect needs experiments that separate them (issue 29: "experiments that
carry information"). Each experiment here keeps both soles flat on the floor and moves the
whole-body CoM on a prescribed path; the joint targets are solved once on the rigid design
model by the whole-body IK (:mod:`zmpkit.sim.whole_body_ik`: both soles held where they
stand, the CoM on its path, the torso upright where the robot names a torso, a small pull
to the standing posture), and played open loop, so every candidate of a fit gets the same
targets (the fit replays them as a step trial, :mod:`zmpkit.simfit.rollout`).

Every experiment starts from the simulator's standing pose and first lowers the CoM by
:math:`\Delta z` (the crouch the robot walks in, else :data:`CROUCH_SHARE` of its standing
CoM height) along a quintic over :data:`RAMP_S`, so the knees carry load; then:

- ``crouch_hold`` holds it (:data:`HOLD_S`): the static deflection of servo, gears and
  links under the robot's weight, the F-T offsets and the mass distribution (the ZMP at
  rest is the CoM's ground projection);
- ``squat``: :math:`c_z(t) = c_{z,0} - \Delta z - \tfrac12 A_z (1 - \cos 2\pi f_s t)`, a slow
  squat of :data:`SQUAT_SHARE` of the standing height at :data:`SQUAT_HZ`: the load on
  knees and ankles changes, which the gear and link compliances feel;
- ``sway_sagittal``: :math:`c_x(t) = A(t) \sin\varphi(t)`, a linear chirp from
  :data:`CHIRP_HZ` [0] to [1] over :data:`CHIRP_S`: the ankles' servos, gear damping and
  backlash across frequencies. The LIPM's ZMP of a CoM swaying at :math:`\omega` moves
  :math:`A (1 + \omega^2 z_c / g)`; the amplitude :math:`A(t) = A_p / (1 + \omega(t)^2 z_c / g)`
  keeps that at :math:`A_p`, a quarter of the half sole length, at every frequency;
- ``sway_frontal``: :math:`c_y(t) = A_y \sin 2\pi f_s t`, :math:`A_y` a quarter of half
  the feet's separation: the roll joints and the F-T sensors' share of the load.

Amplitudes are shares of the robot's own sole and stance, so a kid-size robot and an adult
one get the same excitation relative to their support; the CoM stays well inside it.
Design knowledge only: the rigid model at its standing pose.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.models.pendulum import STANDARD_GRAVITY_MPS2
from zmpkit.robots.robot import Robot
from zmpkit.sim.names import sole_site
from zmpkit.sim.whole_body_ik import IkCosts, IkStop, WholeBodyIk

__all__ = [
    "CHIRP_HZ",
    "CHIRP_S",
    "CROUCH_SHARE",
    "DESIGNS",
    "HOLD_S",
    "RAMP_S",
    "SQUAT_HZ",
    "SQUAT_SHARE",
    "DoubleSupportTargets",
    "double_support_targets",
]

RAMP_S = 1.5
"""Time to lower the CoM into the crouch [s]."""
HOLD_S = 3.5
"""``crouch_hold``'s hold [s]."""
CROUCH_SHARE = 0.08
"""Crouch of a robot that does not walk, share of its standing CoM height [-]."""
SQUAT_SHARE = 0.04
"""``squat``'s CoM travel, share of the standing CoM height [-]."""
SQUAT_HZ = 0.5
"""``squat``'s and ``sway_frontal``'s frequency [Hz]."""
MOTION_S = 4.0
"""``squat``'s and ``sway_frontal``'s motion after the ramp [s]."""
CHIRP_HZ = (0.3, 2.5)
"""``sway_sagittal``'s chirp, first and last frequency [Hz]."""
CHIRP_S = 6.0
"""``sway_sagittal``'s chirp [s]."""
SWAY_SHARE = 0.25
"""Sway amplitude, share of half the sole length (sagittal) or half the stance (frontal) [-]."""
DESIGNS = ("crouch_hold", "squat", "sway_sagittal", "sway_frontal")
"""The designed double-support experiments."""

_IK_PERIOD_S = 0.02
_IK_DT_S = 0.01
_COSTS = IkCosts(foot=10.0, com=10.0, posture=1e-2, equality=100.0)
_TORSO_COSTS = IkCosts(foot=10.0, com=10.0, posture=1e-2, torso=1.0, equality=100.0)
_STOP = IkStop(tolerance_m=1e-4, max_iterations=30)


@dataclass(frozen=True, eq=False)
class DoubleSupportTargets:
    """One designed experiment's joint targets.

    Attributes:
        name: one of :data:`DESIGNS`.
        plane: the plane its trunk tilt is read in (``"sagittal"`` or ``"frontal"``).
        time_s: sample times from the start [s], shape (N,), uniformly spaced.
        joint_names: the driven joints, columns of ``q_rad``.
        q_rad: joint targets [rad], shape (N, J).
        com_error_m: the largest CoM error the IK left [m].
        ramp_s: when the crouch is reached [s].
    """

    name: str
    plane: str
    time_s: NDArray[np.float64]
    joint_names: tuple[str, ...]
    q_rad: NDArray[np.float64]
    com_error_m: float
    ramp_s: float


def _quintic(u: float) -> float:
    """0 → 1 with zero velocity and acceleration at both ends, ``u`` in [0, 1] [-]."""
    u = min(max(u, 0.0), 1.0)
    return u**3 * (10.0 - 15.0 * u + 6.0 * u * u)


def _path(name: str, crouch_m: float, height_m: float, sole_m: float, stance_m: float) -> tuple[
    Callable[[float], NDArray[np.float64]], float, str
]:  # fmt: skip
    """The CoM offset from standing [m] as a function of time [s], the duration [s], plane."""

    def down(t: float) -> NDArray[np.float64]:
        return np.array([0.0, 0.0, -crouch_m * _quintic(t / RAMP_S)])

    if name == "crouch_hold":
        return down, RAMP_S + HOLD_S, "sagittal"
    if name == "squat":
        amplitude = SQUAT_SHARE * height_m

        def squat(t: float) -> NDArray[np.float64]:
            s = max(t - RAMP_S, 0.0)
            extra = 0.5 * amplitude * (1.0 - math.cos(2.0 * math.pi * SQUAT_HZ * s))
            return down(t) - np.array([0.0, 0.0, extra])

        return squat, RAMP_S + MOTION_S, "sagittal"
    if name == "sway_sagittal":
        zmp_amplitude, (f0, f1) = SWAY_SHARE * sole_m / 2.0, CHIRP_HZ
        lipm = (height_m - crouch_m) / STANDARD_GRAVITY_MPS2  # z_c / g [s²]

        def chirp(t: float) -> NDArray[np.float64]:
            s = max(t - RAMP_S, 0.0)
            rate = (f1 - f0) / CHIRP_S
            phase = 2.0 * math.pi * (f0 * s + 0.5 * rate * s * s)
            omega = 2.0 * math.pi * (f0 + rate * s)
            amplitude = zmp_amplitude / (1.0 + omega * omega * lipm)
            return down(t) + np.array([amplitude * math.sin(phase), 0.0, 0.0])

        return chirp, RAMP_S + CHIRP_S, "sagittal"
    if name == "sway_frontal":
        amplitude = SWAY_SHARE * stance_m / 2.0

        def sway(t: float) -> NDArray[np.float64]:
            s = max(t - RAMP_S, 0.0)
            return down(t) + np.array([0.0, amplitude * math.sin(2 * math.pi * SQUAT_HZ * s), 0.0])

        return sway, RAMP_S + MOTION_S, "frontal"
    raise ParameterError(f"unknown double-support experiment {name!r}; valid: {', '.join(DESIGNS)}")


def double_support_targets(robot: Robot, name: str, period_s: float = 0.01) -> DoubleSupportTargets:
    """Solve experiment ``name``'s joint targets on ``robot``'s design model (module docstring).

    Args:
        robot: the robot (two feet on the floor at its standing pose).
        name: one of :data:`DESIGNS`.
        period_s: the targets' sample period [s].
    """
    sim = robot.make_simulation("none")
    model, standing = sim.model, sim.data.qpos.copy()
    height = float(sim.data.subtree_com[0][2])
    soles = {foot.foot: sole_site(foot.foot) for foot in sim.robot.feet}
    sole_xy = [sim.data.site(site).xpos[:2].copy() for site in soles.values()]
    stance = float(np.linalg.norm(sole_xy[0] - sole_xy[1])) if len(sole_xy) == 2 else 0.0
    walking = robot.walking
    if walking is not None:
        crouch = max(height - walking.com_height_m, CROUCH_SHARE * height)
        sole_length = walking.sole_size_m[0]
        torso = walking.ik_settings.torso_body
    else:
        crouch, sole_length, torso = CROUCH_SHARE * height, 0.5 * stance, None
    path, duration, plane = _path(name, crouch, height, sole_length, stance)
    costs = _COSTS if torso is None else _TORSO_COSTS
    ik = WholeBodyIk(model, standing, soles, costs, torso_body=torso)
    ik.hold_frames()
    c0 = np.array(sim.data.subtree_com[0])
    joints = sim.joint_names
    adr = [int(model.joint(j).qposadr[0]) for j in joints]
    grid = np.arange(0.0, duration + 1e-9, _IK_PERIOD_S)
    solved, worst = [], 0.0
    for t in grid:
        ik.com.set_target(c0 + path(float(t)))
        worst = max(worst, ik.solve(_IK_DT_S, _STOP).com_m)
        solved.append(ik.configuration.q[adr].copy())
    table = np.array(solved)
    time_s = np.arange(period_s, duration + 1e-9, period_s)
    q = np.column_stack([np.interp(time_s, grid, table[:, k]) for k in range(len(joints))])
    return DoubleSupportTargets(name, plane, time_s, tuple(joints), q, worst, RAMP_S)
