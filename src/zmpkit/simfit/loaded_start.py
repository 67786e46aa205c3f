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
bisection puts it at the edge the estimated load points to. Checked against a simulated
G1's own gears, those carrying more than 4 N·m are placed to 0.2 mrad and those under
2 N·m miss by 1.3–1.6 mrad on average (half of them are inside the band); the true
accelerations added to the load do not help, the band's history would.

So each compliant degree of freedom :math:`p` (a hinge or slide with a spring and no
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

from collections.abc import Mapping, Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sim.description import FootSensor

__all__ = ["DEFLECTION_BRACKET", "compliant_dofs", "settle_compliance"]

DEFLECTION_BRACKET = 0.5
"""Half-width of the bisection's bracket around zero deflection [rad or m]."""
_BISECTIONS = 48
"""Halvings of the bracket: 1 / 2^48 of it, below float64's resolution of the angle."""
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
        moment = moment_s - np.cross(data.subtree_com[body] - origin, weight)
        mujoco.mj_applyFT(model, data, force, moment, origin, body, out)
    return out


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
    qadr, dofadr = model.jnt_qposadr[joints], model.jnt_dofadr[joints]
    data.qvel[dofadr] = 0.0
    mujoco.mj_fwdPosition(model, data)
    mujoco.mj_fwdVelocity(model, data)
    other = data.qfrc_passive[dofadr] - data.qfrc_spring[dofadr]
    target = (
        data.qfrc_bias[dofadr] - other - _contact_generalized(model, data, feet, wrenches)[dofadr]
    )
    low = np.full(joints.size, -DEFLECTION_BRACKET)
    high = np.full(joints.size, DEFLECTION_BRACKET)
    for _ in range(_BISECTIONS):  # the spring force falls as the coordinate rises
        mid = 0.5 * (low + high)
        above = _spring_force(model, data, qadr, dofadr, mid) > target
        low = np.where(above, mid, low)
        high = np.where(above, high, mid)
    deflection = 0.5 * (low + high)
    data.qpos[qadr] = deflection
    mujoco.mj_tendon(model, data)
    return deflection
