r"""The unmeasured compliance at a shooting window's start, from the load the F-T sensors read.

A robot's encoders sit on the motor side: a gear's deflection and a link's flex are not
measured. A window started with them at zero (:mod:`~zmpkit.simfit.shooting`) releases at
its first tick the load they carried, and the candidate's whole body rings at the compliance's
frequency. The softer the candidate's compliance, the larger the deflection it should have
started with and the larger the release, so the fit's cost drifts towards stiff candidates: on
a 33 kg humanoid (a Unitree G1 ``robot.yaml``, gear stiffness 12 075 N·m/rad, knees
deflecting 5 mrad) the true parameters' mean window cost was 0.587 and a gear 2.5 times
stiffer 0.364; started at the load's equilibrium, 0.255 and 0.235.

A gear inside its dead band carries no load that says where in the band it sits; the
equilibrium alone puts it at the edge the estimated load points to. So a coordinate near its
band is replayed from the load the sensors measured over the rows before the start
(:func:`replay_compliance`, :data:`~zmpkit.simfit.shooting_window.LOAD_HISTORY_S`); the others
start at their equilibrium. Measured against the simulation's hidden angles of the gears, at
the starts of 0.5 s windows (0.3 s burn-in) cut from 6 s open-loop walks' logs (one-off
script, effects M, G; mean and 90th-percentile error over every gear and start), equilibrium
alone → with the history:

- G1 (``robot.yaml``): 0.1 m/s mean 0.32 → 0.17 mrad, p90 0.64 → 0.42; 0.2 m/s 0.32 → 0.17,
  0.96 → 0.47; 0.15 m/s (held out) 0.33 → 0.17, 0.65 → 0.39;
- the built-in walker (P gain 0.9×, gear stiffness 0.7× the shipped robot's): 0.1 m/s 0.11 → 0.11,
  0.22 → 0.23; 0.2 m/s 0.25 → 0.25, 0.87 → 0.65; 0.15 m/s (held out) 0.17 → 0.15,
  0.53 → 0.35.

:data:`NEAR_BAND` was chosen between 1.5 and 3 on the 0.1 and 0.2 m/s walks; replaying every
coordinate did worse on the walker (0.2 m/s: 0.27, p90 0.79): a loaded gear's 1-D replay rings
where the contact holds it. The history costs 9 ms of CPU a start on the walker and 14 ms on the
G1 (10 % and 5 % of a window's rollout).

The equilibrium: each compliant degree of freedom :math:`p` (a hinge or slide with a spring and no
actuator: the gear deflections of effect G, the link flex of effect F) starts at its
quasi-static equilibrium (:math:`\ddot q = 0`) under the measured state and load:

.. math:: f^{spring}_p(\delta_p) = b_p(q, \dot q) - f^{other}_p - \sum_B (J_B^\top w_B)_p

with :math:`b` MuJoCo's bias force (gravity, Coriolis and centrifugal), :math:`f^{other}`
the passive forces other than the springs (damping at the measured speeds, gravity
compensation) and :math:`w_B` the contact wrench on foot body :math:`B`, from its sensor's
reading :math:`(F_s, \tau_s)`, the wrench the foot's subtree (mass :math:`m_B`, centre of
mass :math:`c_B`) exerts on the leg above the sensor origin :math:`o`, taken as static:

.. math:: F_c = F_s - m_B\,g, \qquad \tau_{c,o} = \tau_s - (c_B - o) \times m_B\,g

(:math:`g = (0, 0, -9.81)` m/s²). Each spring's force depends on its own coordinate only (a
joint spring, or a fixed tendon on that one joint, dead band included) and falls
monotonically with it, so each :math:`\delta_p` is found by bisection on
:data:`DEFLECTION_BRACKET` [rad or m], one vectorised pass over every compliant coordinate; a
load beyond what the spring holds there leaves it at the bracket's edge. The joint speeds of
the compliant coordinates start at zero. Only sensor readings and the candidate's own model
enter: nothing of the recording's hidden truth.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sim.description import FootSensor

__all__ = [
    "DEFLECTION_BRACKET",
    "NEAR_BAND",
    "compliance_load",
    "compliant_dofs",
    "replay_compliance",
    "settle_compliance",
]

DEFLECTION_BRACKET = 0.5
"""Half-width of the bisection's bracket around zero deflection [rad or m]."""
_BISECTIONS = 48
"""Halvings of the bracket: 1 / 2^48 of it, below float64's resolution of the angle."""
NEAR_BAND = 1.5
"""A compliant coordinate whose equilibrium lies within this many dead-band half-widths of
zero is replayed from the load's history, the others put at their equilibrium
(:func:`replay_compliance`) [-]."""
_PASSIVE_TYPES = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))


def compliant_dofs(
    model: mujoco.MjModel, data: mujoco.MjData, driven: Sequence[str]
) -> NDArray[np.int64]:
    """The joints of ``model`` that only a spring holds: (joint ids), shape (K,).

    A hinge or slide that is not in ``driven``, carries no actuator and whose spring force
    changes between the ends of :data:`DEFLECTION_BRACKET` (probed on ``data``, restored).
    """
    driven_ids = {int(model.joint(j).id) for j in driven}
    actuated = {
        int(model.actuator_trnid[a, 0])
        for a in range(model.nu)
        if int(model.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT)
    }
    candidates = np.array(
        [
            j
            for j in range(model.njnt)
            if int(model.jnt_type[j]) in _PASSIVE_TYPES and j not in driven_ids | actuated
        ],
        dtype=np.int64,
    )
    if candidates.size == 0:
        return candidates
    qadr = model.jnt_qposadr[candidates]
    dofadr = model.jnt_dofadr[candidates]
    saved = data.qpos[qadr].copy()
    low = _spring_force(model, data, qadr, dofadr, np.full(qadr.size, -DEFLECTION_BRACKET))
    high = _spring_force(model, data, qadr, dofadr, np.full(qadr.size, DEFLECTION_BRACKET))
    data.qpos[qadr] = saved
    mujoco.mj_tendon(model, data)
    return candidates[np.abs(high - low) > 0.0]


def _spring_force(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    qadr: NDArray[np.int64],
    dofadr: NDArray[np.int64],
    position: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The springs' generalized force at the coordinates ``position`` [N·m or N]."""
    data.qpos[qadr] = position
    mujoco.mj_tendon(model, data)
    mujoco.mj_passive(model, data)
    return np.asarray(data.qfrc_spring[dofadr])


def _contact_generalized(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    feet: Sequence[FootSensor],
    wrenches: Mapping[str, NDArray[np.float64]],
) -> NDArray[np.float64]:
    r""":math:`\sum_B J_B^\top w_B` of the feet's contact wrenches (module docstring) [N·m]."""
    out = np.zeros(model.nv)
    gravity = np.asarray(model.opt.gravity, dtype=np.float64)
    for sensor in feet:
        wrench = np.asarray(wrenches[sensor.foot], dtype=np.float64)
        site = model.site(sensor.site).id
        body = int(model.site_bodyid[site])
        force_s, moment_s = wrench_in_world(data.site_xmat[site], wrench)
        weight = float(model.body_subtreemass[body]) * gravity
        origin = data.site_xpos[site]
        force = force_s - weight
        moment = moment_s - _cross(data.subtree_com[body] - origin, weight)
        mujoco.mj_applyFT(model, data, force, moment, origin, body, out)
    return out


def compliance_load(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    joints: NDArray[np.int64],
    feet: Sequence[FootSensor],
    wrenches: Mapping[str, NDArray[np.float64]],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    r"""The load on the compliant coordinates ``joints`` in ``data``'s state, and their inertia.

    ``data`` holds a measured state with the compliant coordinates at zero; their speeds are
    zeroed. The load is the right-hand side of the module docstring's equilibrium,
    :math:`b_p - f^{other}_p - \sum_B (J_B^\top w_B)_p`; the inertia is the joint-space
    inertia matrix's diagonal :math:`M_{pp}`.

    Returns:
        The load [N·m or N] and the inertia [kg·m² or kg], each shape (K,).
    """
    dofadr = model.jnt_dofadr[joints]
    data.qvel[dofadr] = 0.0
    mujoco.mj_fwdPosition(model, data)
    mujoco.mj_fwdVelocity(model, data)
    other = data.qfrc_passive[dofadr] - data.qfrc_spring[dofadr]
    load = (
        data.qfrc_bias[dofadr] - other - _contact_generalized(model, data, feet, wrenches)[dofadr]
    )
    inertia = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, inertia)
    return load, np.array(np.diag(inertia)[dofadr])


def _equilibrium(
    model: mujoco.MjModel, data: mujoco.MjData, joints: NDArray[np.int64], load: NDArray
) -> NDArray[np.float64]:
    """Each spring's coordinate where its force equals ``load``, by bisection [rad or m]."""
    # the spring force falls as the coordinate rises
    return _bisection(model, data, joints, -DEFLECTION_BRACKET, lambda force: force > load)


def _bisection(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    joints: NDArray[np.int64],
    low_end: float,
    below: Callable[[NDArray[np.float64]], NDArray[np.bool_]],
) -> NDArray[np.float64]:
    """Each coordinate's point in [``low_end``, :data:`DEFLECTION_BRACKET`] [rad or m].

    The point where its spring force stops meeting ``below``: met below it, not above.
    """
    qadr, dofadr = model.jnt_qposadr[joints], model.jnt_dofadr[joints]
    low, high = np.full(joints.size, low_end), np.full(joints.size, DEFLECTION_BRACKET)
    for _ in range(_BISECTIONS):
        mid = 0.5 * (low + high)
        met = below(_spring_force(model, data, qadr, dofadr, mid))
        low = np.where(met, mid, low)
        high = np.where(met, high, mid)
    return 0.5 * (low + high)


def _cross(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """The cross product a × b of two 3-vectors (numpy's ``cross`` costs more here)."""
    return np.array(
        (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    )


def settle_compliance(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    driven_joints: Sequence[str],
    feet: Sequence[FootSensor],
    wrenches: Mapping[str, NDArray[np.float64]],
) -> NDArray[np.float64]:
    """Put every compliant coordinate of ``data`` at its equilibrium under the measured load.

    ``data`` holds the measured state (driven joints, base, speeds) with the compliant
    coordinates at zero; their positions are set (module docstring) and their speeds zeroed.
    The positions of the other coordinates are not touched: re-place the base afterwards.

    Args:
        model: the candidate's model.
        data: its data, in the measured state.
        driven_joints: the joints the servos hold (never compliant).
        feet: the feet's F-T sensors.
        wrenches: each foot's sensor-frame reading (foot name → (F_x, F_y, F_z, τ_x, τ_y,
            τ_z)) [N, N·m].

    Returns:
        The deflections [rad or m], in :func:`compliant_dofs`' order, shape (K,).
    """
    joints = compliant_dofs(model, data, driven_joints)
    if joints.size == 0:
        return np.zeros(0)
    load, _ = compliance_load(model, data, joints, feet, wrenches)
    deflection = _equilibrium(model, data, joints, load)
    _place(model, data, joints, deflection, np.zeros(joints.size))
    return deflection


def _place(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    joints: NDArray[np.int64],
    position: NDArray[np.float64],
    speed: NDArray[np.float64],
) -> None:
    data.qpos[model.jnt_qposadr[joints]] = position
    data.qvel[model.jnt_dofadr[joints]] = speed
    mujoco.mj_tendon(model, data)


def _damping(model: mujoco.MjModel, data: mujoco.MjData, joints: NDArray[np.int64]) -> NDArray:
    """Each compliant coordinate's viscous damping, probed at unit speed [N·m·s/rad or N·s/m].

    Joint and tendon damping are linear in the speed; ``data``'s speeds are restored.
    """
    dofadr = model.jnt_dofadr[joints]
    saved = data.qvel.copy()
    data.qvel[:] = 0.0
    data.qvel[dofadr] = 1.0
    mujoco.mj_fwdVelocity(model, data)
    damping = -np.array(data.qfrc_damper[dofadr])
    data.qvel[:] = saved
    mujoco.mj_fwdVelocity(model, data)
    return damping


def _band_edges(
    model: mujoco.MjModel, data: mujoco.MjData, joints: NDArray[np.int64]
) -> NDArray[np.float64]:
    """How far each spring's coordinate moves from zero before it pushes back [rad or m].

    The half-width of a dead band (a fixed tendon's spring range); zero for a plain spring.
    Found by bisection on where the spring force leaves zero, on the positive side.
    """
    return _bisection(model, data, joints, 0.0, lambda force: force == 0.0)


def replay_compliance(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    joints: NDArray[np.int64],
    time_s: NDArray[np.float64],
    load: NDArray[np.float64],
    inertia: NDArray[np.float64],
) -> NDArray[np.float64]:
    r"""Put the compliant ``joints`` where the measured load and its recent history hold them.

    A coordinate whose equilibrium under the last row's load lies beyond
    :data:`NEAR_BAND` times its dead band's half-width is put there
    (:func:`settle_compliance`): the load holds it. One nearer (or inside) its band carries no
    load that says where in the band it sits; its last swings under the load do. From its
    equilibrium under the oldest row's load, each such coordinate is integrated alone on
    its own spring, damping and inertia, the load interpolated linearly between the rows,
    to the last row (the window's start):

    .. math:: M_{pp}\,\ddot\delta_p = f^{spring}_p(\delta_p) - c_p\,\dot\delta_p - \ell_p(t)

    (:math:`\ell_p` the load of :func:`compliance_load`, taken at each tick's start,
    :math:`c_p` the damping), by semi-implicit Euler at the model's time step with the
    damping implicit, as MuJoCo's Euler integrator steps a joint. The couplings between
    coordinates (the off-diagonal inertia, the contacts, the driven joints' accelerations)
    are left out, so the replayed speeds are not the robot's, and a loaded coordinate's
    replay rings where the contact holds it: the coordinates start at rest, and only those
    near their band are replayed (module docstring: the measured errors).
    ``data`` holds the start's measured state; the compliant coordinates' positions are set
    and their speeds zeroed, the rest not touched: re-place the base afterwards.

    Args:
        model: the candidate's model.
        data: its data, in the start's measured state.
        joints: the compliant joints (:func:`compliant_dofs`), shape (K,).
        time_s: the rows' times, the start's last [s], shape (H,), H ≥ 1.
        load: the load of each row [N·m or N], shape (H, K).
        inertia: :math:`M_{pp}` of each row [kg·m² or kg], shape (H, K).

    Returns:
        The deflections at the last row [rad or m], shape (K,).
    """
    position = _equilibrium(model, data, joints, load[-1])
    near = np.abs(position) <= NEAR_BAND * _band_edges(model, data, joints)
    if not near.any() or time_s.size < 2:
        _place(model, data, joints, position, np.zeros(joints.size))
        return position
    replayed, load, inertia = joints[near], load[:, near], inertia[:, near]
    qadr, dofadr = model.jnt_qposadr[replayed], model.jnt_dofadr[replayed]
    damping = _damping(model, data, replayed)
    moving = _equilibrium(model, data, replayed, load[0])
    speed = np.zeros(replayed.size)
    dt = float(model.opt.timestep)
    for row in range(1, time_s.size):
        span = float(time_s[row] - time_s[row - 1])
        ticks = max(1, round(span / dt))
        h = span / ticks
        load_step = (load[row] - load[row - 1]) / ticks
        inertia_step = (inertia[row] - inertia[row - 1]) / ticks
        now_load, now_inertia = load[row - 1].copy(), inertia[row - 1].copy()
        for _ in range(ticks):
            spring = _spring_force(model, data, qadr, dofadr, moving)
            speed = (speed + h * (spring - now_load) / now_inertia) / (
                1.0 + h * damping / now_inertia
            )
            moving = moving + h * speed
            now_load += load_step
            now_inertia += inertia_step
    position[near] = np.minimum(np.maximum(moving, -DEFLECTION_BRACKET), DEFLECTION_BRACKET)
    _place(model, data, joints, position, np.zeros(joints.size))
    return position
