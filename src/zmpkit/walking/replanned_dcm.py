r"""The DCM, ZMP and CoM references of a walk whose steps move (the ``dcm`` walk's).

A step of the plan from the stance sole ``S^{ref}`` to the landing ``U`` at ``T``, re-planned
to land at ``G`` at ``T'`` (the stance sole itself moved by ``o_s``: ``S = S^{ref} + o_s``),
changes the ZMP reference by

.. math:: δp(t) = o_s + (G - S)\, r(t - T') - (U - S^{ref})\, r(t - T)

(``r`` the unit transfer over the double support ``T_d``). The DCM reference changes by the
DCM of that change, ``δξ(t) = ω ∫_t^∞ e^{-ω(s-t)} δp(s) ds``:

.. math:: δξ(t) = o_s + (G - S)\, Ξ(T' - t) - (U - S^{ref})\, Ξ(T - t),

``Ξ`` the DCM of the unit transfer (:func:`~zmpkit.walking.capture_step.transfer_dcm`). The
CoM reference follows the DCM as the LIPM's does, ``δ\dot c = ω (δξ - δc)``, so it does not
jump when ``δξ`` does; then ``δ\ddot c = ω^2 (δc - δp)`` (the LIPM's ``p = c - \ddot c/ω^2``).
A tick is scalar arithmetic written into an array.
"""

from __future__ import annotations

import numpy as np

from zmpkit.walking.capture_step import transfer_dcm, transfer_zmp
from zmpkit.walking.planned_steps import PlannedStep

__all__ = ["ReplannedDcmReference"]


class ReplannedDcmReference:
    """The change of the DCM, ZMP and CoM references (module docstring), one period a time.

    Args:
        omega_per_s: ω [1/s].
        period_s: the control period [s].
        double_support_s: T_d [s].

    Attributes:
        shift: rows x, y: δc [m], δċ [m/s], δc̈ [m/s²], δp [m], δξ [m] of the last
            :meth:`update`, shape (2, 5).
        com_next: δc (x, y) of the period after it [m], shape (2,).
    """

    def __init__(self, omega_per_s: float, period_s: float, double_support_s: float) -> None:
        self._omega, self._dt, self._t_d = omega_per_s, period_s, double_support_s
        self.shift = np.zeros((2, 5))
        self.com_next = np.zeros(2)

    def update(
        self, step: PlannedStep, before: int, stance_offset: list[float], goal: list[float],
        touchdown: float,
    ) -> None:  # fmt: skip
        """The references' change at period ``before`` of ``step``'s span.

        Args:
            step: the step under way (its plan).
            before: the period [-].
            stance_offset: o_s (x, y) [m].
            goal: G (x, y) [m].
            touchdown: T' [periods].
        """
        omega, dt, t_d = self._omega, self._dt, self._t_d
        planned = (step.touchdown - before) * dt
        zmp_plan, dcm_plan = transfer_zmp(t_d, planned), transfer_dcm(omega, t_d, planned)
        ahead = (touchdown - before) * dt
        zmp_new, dcm_new = transfer_zmp(t_d, ahead), transfer_dcm(omega, t_d, ahead)
        self._axis(0, stance_offset[0], goal[0] - step.stance_x, step.land_x - step.stance_x,
                   zmp_new, zmp_plan, dcm_new, dcm_plan)  # fmt: skip
        self._axis(1, stance_offset[1], goal[1] - step.stance_y, step.land_y - step.stance_y,
                   zmp_new, zmp_plan, dcm_new, dcm_plan)  # fmt: skip

    def _axis(
        self, axis: int, o: float, to_goal: float, to_land: float, zmp_new: float,
        zmp_plan: float, dcm_new: float, dcm_plan: float,
    ) -> None:  # fmt: skip
        """One axis: δp, δξ and the CoM that follows (``to_goal = G - S^{ref}``)."""
        omega, shift = self._omega, self.shift
        zmp = o + (to_goal - o) * zmp_new - to_land * zmp_plan
        dcm = o + (to_goal - o) * dcm_new - to_land * dcm_plan
        com = self.com_next.item(axis)
        rate = omega * (dcm - com)
        shift[axis, 0], shift[axis, 1], shift[axis, 2] = com, rate, omega * omega * (com - zmp)
        shift[axis, 3], shift[axis, 4] = zmp, dcm
        self.com_next[axis] = com + self._dt * rate
