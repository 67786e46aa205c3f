r"""The DCM stabiliser of a position-controlled walk: a CoM correction from the DCM error.

Today's walking controllers stabilise the divergent component of motion (Englsberger, Ott
and Albu-Schäffer, "Three-dimensional bipedal walking control based on divergent component
of motion", IEEE T-RO 31, 2015; Caron et al., "Stair climbing stabilization of the HRP-4
humanoid robot using whole-body admittance control", ICRA 2019, the lipm_walking_controller).
With ``ω = √(g/z_c)`` the DCM is ``ξ = c + ċ/ω`` and, for the LIPM, ``ξ̇ = ω (ξ - p)``: the ZMP
``p`` pushes the DCM away from itself, so a DCM ahead of its plan needs a ZMP ahead of the
planned one. A position-controlled robot cannot ask for a ZMP; it moves its CoM. Per
horizontal axis, a correction ``Δc`` is added to the planned CoM ``c^{ref}``:

.. math:: Δ\ddot c = -ω\,Δ\dot c - ω K_ξ \Big(e + K_i \int e\,dt\Big)
    + A_c\,\operatorname{clip}(p - p^d, ±δ_A), \qquad e = \hat ξ - ξ^{ref}.

If the robot tracks its CoM command, ``e = Δc + Δ\dot c/ω`` plus what disturbed it, and
without admittance ``\dot e = Δ\dot c + Δ\ddot c/ω = -K_ξ e``: the loop's poles are ``-ω``
and ``-K_ξ``, the DCM error decays at ``K_ξ`` [1/s] and the correction stays bounded. The ZMP
this asks of the robot is ``p^d = p^{ref} - Δ\ddot c/ω^2`` (the LIPM's ``p = c - \ddot
c/ω^2``). The CoM admittance ``A_c`` [1/s²] moves the measured ZMP towards ``p^d``: at the
robot's 2 Hz rocking a ZMP ahead of the asked one accelerates the CoM forwards, which moves
the ZMP backwards (``p = c - \ddot c/ω^2``), and damps it. Statically it pushes the wrong
way (a CoM moved forwards moves the ZMP forwards). For a robot that follows its command,
``p = p^{ref} + Δc - Δ\ddot c/ω^2 + d_0`` with a ZMP error ``d_0``, the loop is

.. math:: Δ\ddot c = -(ω + K_ξ)\,Δ\dot c - ω K_ξ\,Δc + A'_c\,(Δc + d_0), \qquad
    A'_c = \frac{A_c ω^2}{ω^2 + A_c},

with the characteristic polynomial ``s^2 + (ω + K_ξ) s + ω K_ξ - A'_c``: stable only if
``A'_c < ω K_ξ``. In discrete time the ZMP read at a period carries the acceleration
commanded one period before and the observer adds its own lag, so the bound is lower still:
the stabiliser checks its gains on the exact discrete loop with such a robot
(:func:`follower_spectral_radius`, below 1) and refuses gains that would ring or drift. A
steady ZMP error the observer cannot see as a CoM error settles at
``Δc = A'_c d_0 / (ω K_ξ - A'_c)``. The admittance's error is
clipped to ``±δ_A``, because a ZMP at the sole's edge or on the wrong foot in a support
change says nothing a CoM shift can fix. ``Δ\ddot c`` is clamped so that ``|p^d - p^{ref}|
≤`` ``max_zmp_shift_m``, ``|Δc| ≤`` ``max_com_shift_m``.

**The DCM estimate.** Differentiating the kinematic CoM (encoders and IMU) gives a DCM that
carries the robot's 2 Hz trunk and foot rocking: fed back directly, any gain above 0.1 1/s
made the virtual walking robot with all effects fall (the first version needed a 3 cm dead
band and then did little). The estimate here is the ZMP observer's
(:mod:`zmpkit.walking.zmp_observer`, the same ``A_z``, ``C`` and Kalman gain ``L``) run on
the *command error*: a position-controlled robot follows its command, so its state is the
commanded CoM ``(c, ċ, c̈)_{cmd} = c^{ref} + Δc`` (and derivatives) plus an error
``ε = (ε_c, ε_v, ε_a, d)`` that evolves as the cart table driven by unmodelled jerk,
without input:

.. math:: ε^-_{k+1} = A_z ε^+_k, \qquad ε^+_k = ε^-_k + L\,(y_k - C ε^-_k), \qquad
    y_k = \begin{bmatrix} \hat c_k - c_{cmd,k} \\ p_k - (c_{cmd,k}
    - \tfrac{z_c}{g}\ddot c_{cmd,k}) \end{bmatrix},

the ZMP innovation clipped as the observer clips it, and ``\hat ξ = c_{cmd} + ε_c +
(\dot c_{cmd} + ε_v)/ω``. A steady CoM error ``δ`` (measured CoM and ZMP both ``δ`` off the
command) is estimated as ``ε_c = δ``; a steady ZMP-only error as the offset ``d``, which
is not a DCM error.

**How the gains were chosen** (module defaults, with all effects on the virtual walking
robot). Tuning set: four 10 s walks (0.2 and 0.25 m/s at 0.5 s steps, 0.4 s steps, sideways
0.05 m/s). The first version (kinematic DCM, 3 cm dead band, no admittance) stood in 1 of 4.
With this estimate and no dead band, first with a damping term that counted ``K_ξ``
twice (``-(ω + K_ξ) Δ\dot c``): ``A_c = 0`` stood in 0 to 1 of 4 for ``K_ξ`` 0.01–3;
``A_c = 20`` 1/s² with its ZMP error clipped to 3 cm in 3 of 4 (the sideways walk falls),
``K_ξ`` 6, ``A_c`` 40, or a 1.5 cm clip in fewer. With the law as above: ``K_ξ`` 3 and 4
in 3 of 4, 5 in 2; ``A_c`` 15 in 2; between ``K_ξ`` 3 and 4 the lower mean 2 Hz trunk
amplitude of the three walks that stood chose 3 (0.046 against 0.048 rad). The clip then
went to 8 cm (3 of 4 again, mean amplitude 0.037 rad; 6.5 cm: 2 of 4; 10 or 12 cm, or
ignoring larger errors instead of clipping them: as 8 cm). With these gains the loop with a
following robot is stable up to ``A_c ≈ 35.7`` 1/s². In the sideways walk the robot then
still rolled over the outer edge of a foot after its first step; the cause was the swing
sole driven on into the floor it met early, and with :mod:`zmpkit.walking.early_touchdown`
that walk stands (the gains unchanged). Judged on the robustness sweep's other 48 cases
(:mod:`zmpkit.experiments.robustness`), which they were not chosen on: see the sweep.
Foot damping (:mod:`zmpkit.walking.foot_damping`) stays off: with the CoM admittance it
tracks the same ZMP, and at 0.1 rad/(N·m·s) the 3 s walk falls.
"""

from __future__ import annotations

import math
from typing import TypeAlias

import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.walking.dcm_parameters import DcmParameters, require_stable
from zmpkit.walking.scalar_limits import clamp
from zmpkit.walking.zmp_observer import observer_gain, observer_matrices

__all__ = ["DcmStabiliser"]

_Plan: TypeAlias = tuple[list[float], list[float], list[float], list[float], list[float]]
"""One axis of the plan, as floats: c [m], ċ [m/s], c̈ [m/s²], p [m], ξ [m] per period."""


class DcmStabiliser:
    """The CoM correction ``Δc`` of the module docstring, one control period at a time.

    Args:
        com_position_in_world: planned CoM ``c^{ref}`` of every period [m], shape (N, 2).
        com_velocity_in_world: its velocity [m/s], shape (N, 2).
        com_acceleration_in_world: its acceleration [m/s²], shape (N, 2).
        zmp_reference_in_world: planned ZMP ``p^{ref}`` [m], shape (N, 2).
        com_height_m: z_c [m].
        period_s: the control period T [s].
        gravity_mps2: g [m/s²].
        parameters: gains and limits.
    """

    def __init__(
        self,
        com_position_in_world: NDArray[np.float64],
        com_velocity_in_world: NDArray[np.float64],
        com_acceleration_in_world: NDArray[np.float64],
        zmp_reference_in_world: NDArray[np.float64],
        com_height_m: float,
        period_s: float,
        gravity_mps2: float,
        parameters: DcmParameters | None = None,
    ) -> None:
        self.parameters = par = parameters or DcmParameters()
        _validate.positive("com_height_m", com_height_m, "m")
        _validate.positive("period_s", period_s, "s")
        self.period_s = period_s
        self.omega = math.sqrt(gravity_mps2 / com_height_m)
        """ω [1/s]."""
        require_stable(par, com_height_m, period_s, gravity_mps2)
        self._c_ref = np.asarray(com_position_in_world, dtype=np.float64)[:, :2]
        self._v_ref = np.asarray(com_velocity_in_world, dtype=np.float64)[:, :2]
        self._a_ref = np.asarray(com_acceleration_in_world, dtype=np.float64)[:, :2]
        self._p_ref = np.asarray(zmp_reference_in_world, dtype=np.float64)[:, :2]
        self._dcm_ref = self._c_ref + self._v_ref / self.omega
        self._n = self._c_ref.shape[0]
        self._ref_by_axis = [  # per axis: c, ċ, c̈, p, ξ of the plan, as floats (fast to index)
            tuple(x[:, axis].tolist() for x in (
                self._c_ref, self._v_ref, self._a_ref, self._p_ref, self._dcm_ref
            ))
            for axis in (0, 1)
        ]  # fmt: skip
        a_z, _, c_z = observer_matrices(period_s, com_height_m, gravity_mps2)
        gain = observer_gain(par.observer, period_s, com_height_m, gravity_mps2)
        self._a = a_z.tolist()
        self._l = gain.tolist()
        self._zc_over_g = -float(c_z[1, 2])
        self.shift_in_world = np.zeros(2)
        """Δc (x, y) [m]."""
        self.shift_rate_in_world = np.zeros(2)
        """Δċ (x, y) [m/s]."""
        self.shift_acceleration_in_world = np.zeros(2)
        """Δc̈ (x, y) of the last period [m/s²]."""
        self.error_state = np.zeros((2, 4))
        """Prior of the command error ε, rows x, y: ε_c [m], ε_v [m/s], ε_a [m/s²], d [m]."""
        self._integral = np.zeros(2)  # ∫ e dt [m·s]
        self._axes = tuple(  # per axis: its index, its error state's row, the plan's floats
            (axis, self.error_state[axis], self._ref_by_axis[axis]) for axis in (0, 1)
        )
        self.dcm_error_in_world = np.full((self._n, 2), np.nan)
        """The DCM error ``e = ξ̂ - ξ^{ref}`` of each period [m], shape (N, 2)."""
        self.reference_shift = np.zeros((2, 5))
        """What a re-planned walk adds to the plan's references of the next :meth:`update`,
        rows x, y: c [m], ċ [m/s], c̈ [m/s²], p [m], ξ [m], shape (2, 5)
        (:mod:`zmpkit.walking.step_adjustment`); zeros: the plan. The robot does not jump
        with a re-planned command: the command error's velocity and acceleration take back
        what the re-plan changed beyond the reference's own motion."""
        self._moved_before = np.zeros((2, 2))  # rows x, y: ċ, c̈ of the last shift
        self.desired_zmp_in_world = np.full((self._n, 2), np.nan)
        """The ZMP ``p^d`` asked for at each period [m], shape (N, 2)."""

    def dcm_in_world(self, k: int) -> tuple[float, float]:
        """The DCM estimate of period ``k`` [m] from the current error state (x, y)."""
        k = min(k, self._n - 1)
        c, v, e, w = self._c_ref[k], self._v_ref[k], self.error_state, self.omega
        s, r = self.shift_in_world, self.shift_rate_in_world
        return (
            float(c[0] + s[0] + e[0, 0] + (v[0] + r[0] + e[0, 1]) / w),
            float(c[1] + s[1] + e[1, 0] + (v[1] + r[1] + e[1, 1]) / w),
        )

    def update(
        self, k: int, com_in_world: NDArray[np.float64], zmp_in_world: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """One period: correct with the readings of period ``k``, return ``Δc`` of ``k + 1``.

        Args:
            k: the period the readings belong to (its command was ``c^{ref}_k + Δc``) [-].
            com_in_world: the CoM estimated from encoders and IMU (x, y) [m].
            zmp_in_world: the measured ZMP (x, y) [m]; NaN (no contact) skips the correction
                and the admittance.

        Returns:
            Δc (x, y) for period ``k + 1`` [m], a view.
        """
        k = k if k < self._n else self._n - 1  # (min makes an object)
        for axis, z, plan in self._axes:
            self._update_axis(k, axis, z, plan, com_in_world.item(axis), zmp_in_world.item(axis))
        return self.shift_in_world

    def _update_axis(
        self, k: int, axis: int, z: NDArray[np.float64], plan: _Plan, com: float, zmp: float
    ) -> None:
        """:meth:`update` on one axis: correct ε, the DCM law, integrate Δc, predict ε.

        ``z`` is the axis's row of :attr:`error_state`, ``plan`` its planned c, ċ, c̈, p, ξ,
        ``com`` and ``zmp`` its readings [m].
        """
        c_ref, v_ref, a_ref, p_ref, dcm_ref = plan
        moved = self.reference_shift
        e_c, e_v, e_a, d = self._replanned_error(axis, z)
        c_cmd = c_ref[k] + moved.item(axis, 0) + self.shift_in_world.item(axis)
        v_cmd = v_ref[k] + moved.item(axis, 1) + self.shift_rate_in_world.item(axis)
        a_cmd = a_ref[k] + moved.item(axis, 2) + self.shift_acceleration_in_world.item(axis)
        p_plan = p_ref[k] + moved.item(axis, 3)
        has_zmp = math.isfinite(zmp)
        if has_zmp:
            e_c, e_v, e_a, d = self._corrected_error(e_c, e_v, e_a, d, com, zmp, c_cmd, a_cmd)
        error = c_cmd + e_c + (v_cmd + e_v) / self.omega - (dcm_ref[k] + moved.item(axis, 4))
        self.dcm_error_in_world[k, axis] = error
        accel = self._acceleration(axis, error, zmp, has_zmp, p_plan)
        omega = self.omega
        self.desired_zmp_in_world[k, axis] = p_plan - accel / (omega * omega)
        self._integrate_shift(axis, accel)
        (a00, a01, a02, _), (_, a11, a12, _), (_, _, a22, _), _ = self._a
        z[0] = a00 * e_c + a01 * e_v + a02 * e_a
        z[1] = a11 * e_v + a12 * e_a
        z[2] = a22 * e_a
        z[3] = d

    def _replanned_error(
        self, axis: int, z: NDArray[np.float64]
    ) -> tuple[float, float, float, float]:
        """The prior ε_c, ε_v, ε_a, d of the axis, after a re-plan.

        A re-plan moves the command, not the robot: the error state takes back the jump of
        :attr:`reference_shift` beyond the reference's own motion.
        """
        moved, before, dt = self.reference_shift, self._moved_before, self.period_s
        e_c, e_v, e_a, d = z.item(0), z.item(1), z.item(2), z.item(3)
        v_moved, a_moved = moved.item(axis, 1), moved.item(axis, 2)
        v_before, a_before = before.item(axis, 0), before.item(axis, 1)
        e_v -= v_moved - v_before - dt * a_before
        e_a -= a_moved - a_before
        before[axis, 0], before[axis, 1] = v_moved, a_moved
        return e_c, e_v, e_a, d

    def _corrected_error(
        self,
        e_c: float,
        e_v: float,
        e_a: float,
        d: float,
        com: float,
        zmp: float,
        c_cmd: float,
        a_cmd: float,
    ) -> tuple[float, float, float, float]:
        """ε and d corrected by the observer from the CoM [m] and ZMP [m] of the readings."""
        observer = self.parameters.observer
        (l00, l01), (l10, l11), (l20, l21), (l30, l31) = self._l
        zc_g = self._zc_over_g
        r_c = com - c_cmd - e_c
        r_p = zmp - (c_cmd - zc_g * a_cmd) - (e_c - zc_g * e_a + d)
        r_p = clamp(r_p, observer.max_zmp_innovation_m)
        e_c += l00 * r_c + l01 * r_p
        e_v += l10 * r_c + l11 * r_p
        e_a += l20 * r_c + l21 * r_p
        d += l30 * r_c + l31 * r_p
        d = clamp(d, observer.max_offset_m)
        return e_c, e_v, e_a, d

    def _acceleration(
        self, axis: int, error: float, zmp: float, has_zmp: bool, p_plan: float
    ) -> float:
        """Δc̈ [m/s²] from the DCM error [m] (dead band, integral), with the admittance."""
        par, omega, dt = self.parameters, self.omega, self.period_s
        omega2 = omega * omega
        integrals = self._integral
        excess = abs(error) - par.dcm_deadband_m
        error = math.copysign(excess, error) if excess > 0.0 else 0.0
        integral = integrals.item(axis) + error * dt
        integral = clamp(integral, par.integral_limit_m_s)
        integrals[axis] = integral
        rate = self.shift_rate_in_world.item(axis)
        accel = -omega * rate - omega * par.dcm_gain_per_s * (
            error + par.dcm_integral_gain_per_s * integral
        )
        if par.com_admittance_per_s2 > 0.0 and has_zmp:
            zmp_error = zmp - (p_plan - accel / omega2)
            zmp_error = clamp(zmp_error, par.max_admittance_zmp_error_m)
            accel += par.com_admittance_per_s2 * zmp_error
        return clamp(accel, omega2 * par.max_zmp_shift_m)

    def _integrate_shift(self, axis: int, accel: float) -> None:
        """Δc̈ := ``accel`` [m/s²], then Δċ and Δc one period on, Δc held at its limit."""
        dt, shift_limit = self.period_s, self.parameters.max_com_shift_m
        self.shift_acceleration_in_world[axis] = accel
        rate = self.shift_rate_in_world.item(axis) + accel * dt
        shift = self.shift_in_world.item(axis) + rate * dt
        if abs(shift) > shift_limit:
            shift = math.copysign(shift_limit, shift)
            rate = 0.0
        self.shift_in_world[axis] = shift
        self.shift_rate_in_world[axis] = rate
