r"""Soft servos pre-loaded with the torques of the ZMP shift a feedback walk asks for.

A P-only position servo of gain :math:`k` [N·m/rad] (joint side) makes torque only from its
error, :math:`\tau = k (q_{cmd} - q) - b \dot q`. The planned walk's torques are fed forward
over it (:mod:`zmpkit.walking.servo_feedforward`), but a feedback walk that moves the ZMP off
the plan — to stop a push — asks the stance leg for torques the plan never had, and a soft
servo makes them only once the body has already moved away from its command: the ZMP lags
the controller and a push that a stiff robot stops topples a soft one (a 3.2 kg kid-size
robot on Dynamixel servos at their factory P gain, 18.9 N·m/rad: a 0.1 s push of 11.9 N
along x falls with the motor effect and stands without it).

Each tick this module turns the controller's ZMP shift :math:`\Delta p` (x, y) [m] — what
it asks of the ZMP beyond the planned reference — into the joint torques that shift needs
and adds them to the targets as :math:`\Delta q = \Delta\tau / k`. Moving the ZMP of a
vertical load :math:`F_z` by :math:`\Delta p` changes the ground's moment on each loaded sole
by

.. math:: \Delta m_i = F_{z,i}\,(\Delta p_y,\ -\Delta p_x,\ 0)

(the shift taken by every foot in proportion to its measured load), and the joints of the
leg carry it: :math:`\Delta\tau = -\sum_i J_{r,i}^T \Delta m_i`, with :math:`J_{r,i}` the
rotational Jacobian of sole :math:`i` on the design model at the IK's solution (the split of
a contact wrench into joint torques of :func:`~zmpkit.walking.servo_feedforward.
planned_joint_torques`), whose column of a hinge between the sole and the root is the
hinge's axis in the world, :math:`a_j` (a slide joint carries no moment): per joint,
:math:`\Delta\tau_j = -\sum_i a_j \cdot \Delta m_i` over the soles it moves. A foot in the
air carries nothing; a sensor that reads nothing (NaN) keeps its last load, so that its
dropout does not jerk the targets.

The sagittal shift is first low-passed at :data:`SAGITTAL_CUTOFF_PER_STEP_HZ` times the
step frequency: at full bandwidth it shakes the trunk at the step frequency (that robot's
unpushed 0.1 m/s walk: 0.042 rad of trunk pitch against 0.007 rad without the
feed-forward); the lateral shift is not filtered (at full bandwidth it leaves the unpushed
walk's trunk as it was). Filtered, that walk's trunk pitch still doubles (0.0069 → 0.014 rad
at 2 Hz); what it buys is measured in the README (pushes, speed).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate

__all__ = ["SAGITTAL_CUTOFF_PER_STEP_HZ", "ZmpShiftFeedforward"]

SAGITTAL_CUTOFF_PER_STEP_HZ = 0.5
"""Cut-off of the sagittal shift's low-pass, over the step frequency 1/T_step [-] (0.5 s
steps: 1 Hz; the lateral ZMP moves from foot to foot at half the step frequency)."""


class ZmpShiftFeedforward:
    """The joint-target offsets of a ZMP shift over soft servos (module docstring).

    Args:
        model: the design model (the IK's).
        data: its data, the IK's, read at the IK's solution (whose kinematics the IK
            updates after every step: mink's ``Configuration.update``).
        sole_sites: the soles' sites, in the order of the loads given to :meth:`apply`.
        joint_names: the driven joints, in the order of the targets.
        stiffness_nm_per_rad: the servos' P gain at the joint ``k`` [N·m/rad].
        control_period_s: the tick [s].
        step_duration_s: the walk's step duration ``T_step`` [s].
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        sole_sites: Sequence[str],
        joint_names: Sequence[str],
        stiffness_nm_per_rad: float,
        control_period_s: float,
        step_duration_s: float,
    ) -> None:
        self.stiffness_nm_per_rad = _validate.positive(
            "stiffness_nm_per_rad", stiffness_nm_per_rad, "N·m/rad"
        )
        dt = _validate.positive("control_period_s", control_period_s, "s")
        step = _validate.positive("step_duration_s", step_duration_s, "s")
        self.sagittal_cutoff_hz = SAGITTAL_CUTOFF_PER_STEP_HZ / step
        """The sagittal shift's low-pass cut-off [Hz]."""
        self._alpha = 1.0 - math.exp(-2.0 * math.pi * self.sagittal_cutoff_hz * dt)
        self._xaxis = data.xaxis  # a view, made once: the hinges' axes in the world
        sites = [model.site(name).id for name in sole_sites]
        hinge = int(mujoco.mjtJoint.mjJNT_HINGE)
        joints = [model.joint(name) for name in joint_names]
        terms = []  # (target, joint, sole): every hinge between a sole and the root
        for i, site in enumerate(sites):
            body, chain = int(model.site_bodyid[site]), set()
            while body > 0:
                chain.add(body)
                body = int(model.body_parentid[body])
            terms += [
                (j, joint.id, i)
                for j, joint in enumerate(joints)
                if int(joint.type[0]) == hinge and int(joint.bodyid[0]) in chain
            ]
        self._terms = tuple(terms)
        self._feet = tuple(range(len(sites)))
        self._moment_x = [0.0] * len(sites)  # Δm_i about x, y [N·m]
        self._moment_y = [0.0] * len(sites)
        self.shift_in_world = np.zeros(2)
        """The shift last applied, the sagittal one low-passed (x, y) [m]."""
        self._loads = [0.0] * len(sites)  # each sole's last finite load [N]

    def apply(
        self,
        q_target_rad: NDArray[np.float64],
        shift_x_m: float,
        shift_y_m: float,
        force_z_n: NDArray[np.float64],
        threshold_n: float,
    ) -> None:
        """Add the offsets of the shift ``(shift_x_m, shift_y_m)`` [m] to ``q_target_rad``.

        Real-time code: it creates no numpy object and keeps nothing
        (``tests/walking/test_tick_allocations.py``).

        Args:
            q_target_rad: the IK's joint targets [rad], in ``joint_names`` order; written.
            shift_x_m: the ZMP shift asked along the world's x [m] (low-passed here).
            shift_y_m: the ZMP shift asked along the world's y [m].
            force_z_n: each sole's measured vertical load [N], in ``sole_sites`` order; a
                sensor that reads NaN keeps its last finite load.
            threshold_n: the load from which a sole is in contact [N].
        """
        shift = self.shift_in_world
        sx = shift.item(0)
        sx += self._alpha * (shift_x_m - sx)
        shift[0], shift[1] = sx, shift_y_m
        if not (math.isfinite(sx) and math.isfinite(shift_y_m)):
            shift[:] = 0.0  # a NaN never reaches the servos
            return
        loads, moment_x, moment_y = self._loads, self._moment_x, self._moment_y
        loaded = False
        for i in self._feet:
            fz = force_z_n.item(i)
            if math.isfinite(fz):
                loads[i] = fz
            else:  # a sensor that reads nothing: its last load, not a jump of the targets
                fz = loads[i]
            if fz >= threshold_n:
                moment_x[i], moment_y[i] = fz * shift_y_m, -fz * sx  # Δm_i
                loaded = True
            else:
                moment_x[i] = moment_y[i] = 0.0
        if not loaded:
            return
        axis, k = self._xaxis, self.stiffness_nm_per_rad
        for j, joint, i in self._terms:  # Δτ_j = -a_j · Δm_i
            tau = -(axis.item(joint, 0) * moment_x[i] + axis.item(joint, 1) * moment_y[i])
            q_target_rad[j] = q_target_rad.item(j) + tau / k
