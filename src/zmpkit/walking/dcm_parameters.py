"""The DCM stabiliser's gains and limits, and the stability of its loop on a following robot.

:class:`DcmParameters` are the gains and limits of the law of
:mod:`zmpkit.walking.dcm_stabiliser`; :func:`follower_transition` is the loop's transition
over one period on a robot that follows its CoM command, and its spectral radius
(:func:`follower_spectral_radius`) below 1 is what :func:`require_stable` asks of the gains.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.foot_damping import FootDampingParameters
from zmpkit.walking.zmp_observer import ZmpObserverParameters, observer_gain, observer_matrices

__all__ = [
    "MAX_DCM_GAIN_PER_S",
    "DcmParameters",
    "follower_spectral_radius",
    "follower_transition",
    "require_stable",
]

MAX_DCM_GAIN_PER_S = 50.0
"""Largest ``K_ξ`` the 10 ms loop allows [1/s]."""


@dataclass(frozen=True)
class DcmParameters:
    """Gains and limits of the DCM stabiliser (module docstring).

    Attributes:
        dcm_gain_per_s: K_ξ, the DCM error's decay rate [1/s].
        dcm_integral_gain_per_s: K_i [1/s].
        com_admittance_per_s2: A_c [1/s²]; 0 switches the admittance off.
        max_admittance_zmp_error_m: δ_A, the ZMP error the admittance sees is clipped to it [m].
        max_zmp_shift_m: the asked ZMP stays within this of the plan [m].
        max_com_shift_m: the CoM correction stays within this [m].
        integral_limit_m_s: clamp of the DCM error's integral [m·s].
        dcm_deadband_m: DCM errors within ±this get no feedback (beyond it, only the excess
            does) [m]; 0: none.
        observer: the noise levels of the DCM's observer (the ZMP observer's).
        foot_damping: the stance ankles' CoP tracking of ``p^d``
            (:mod:`zmpkit.walking.foot_damping`; admittance 0: off).
    """

    dcm_gain_per_s: float = 3.0
    dcm_integral_gain_per_s: float = 0.0
    com_admittance_per_s2: float = 20.0
    max_admittance_zmp_error_m: float = 0.08
    max_zmp_shift_m: float = 0.03
    max_com_shift_m: float = 0.03
    integral_limit_m_s: float = 0.01
    dcm_deadband_m: float = 0.0
    observer: ZmpObserverParameters = field(default_factory=ZmpObserverParameters)
    foot_damping: FootDampingParameters = field(default_factory=FootDampingParameters)

    def __post_init__(self) -> None:
        for name in (
            "dcm_gain_per_s", "max_zmp_shift_m", "max_com_shift_m",
            "max_admittance_zmp_error_m",
        ):  # fmt: skip
            _validate.positive(f"DcmParameters.{name}", getattr(self, name))
        for name in (
            "dcm_integral_gain_per_s", "com_admittance_per_s2", "integral_limit_m_s",
            "dcm_deadband_m",
        ):  # fmt: skip
            _validate.non_negative(f"DcmParameters.{name}", getattr(self, name))
        if self.dcm_gain_per_s > MAX_DCM_GAIN_PER_S:
            raise ParameterError(
                f"DcmParameters.dcm_gain_per_s must be <= {MAX_DCM_GAIN_PER_S:g} 1/s (the "
                f"10 ms loop's limit); got {self.dcm_gain_per_s}"
            )


def follower_transition(
    parameters: DcmParameters, com_height_m: float, period_s: float, gravity_mps2: float
) -> NDArray[np.float64]:
    r"""The stabiliser's loop with a robot that follows its command, one period [-].

    One axis, no clamps, no dead band: the state ``(ε_c, ε_v, ε_a, d, Δc, Δ\dot c,
    Δ\ddot c_{k-1}, \int e)`` (the integral only with ``K_i > 0``) maps linearly to the
    next period's through the observer's correction and prediction, the law and the
    admittance, with the robot's readings
    ``\hat c = c_{cmd}`` and ``p = c_{cmd} - (z_c/g)\,\ddot c_{cmd}`` (the acceleration
    commanded the period before).

    Returns:
        The transition matrix, shape (7, 7), or (8, 8) with the integral.
    """
    a_z, _, c_z = observer_matrices(period_s, com_height_m, gravity_mps2)
    gain = observer_gain(parameters.observer, period_s, com_height_m, gravity_mps2)
    omega = math.sqrt(gravity_mps2 / com_height_m)
    k_xi, k_i = parameters.dcm_gain_per_s, parameters.dcm_integral_gain_per_s
    admittance = parameters.com_admittance_per_s2
    size = 8 if k_i > 0.0 else 7  # without K_i the integral feeds nothing back
    transition = np.zeros((size, size))
    for column in range(size):
        x = np.zeros(8)
        x[column] = 1.0
        error_state, shift, rate, accel_before, integral = x[:4], x[4], x[5], x[6], x[7]
        error_state = error_state + gain @ (-(c_z @ error_state))  # readings = command
        error = shift + error_state[0] + (rate + error_state[1]) / omega
        integral += error * period_s
        accel = -omega * rate - omega * k_xi * (error + k_i * integral)
        zmp_error = shift - accel_before / omega**2 + accel / omega**2  # p - p^d
        accel += admittance * zmp_error
        rate += accel * period_s
        shift += rate * period_s
        transition[:4, column] = a_z @ error_state
        transition[4:, column] = (shift, rate, accel, integral)[: size - 4]
    return transition


def follower_spectral_radius(
    parameters: DcmParameters, com_height_m: float, period_s: float, gravity_mps2: float
) -> float:
    """Spectral radius of :func:`follower_transition`: the loop is stable below 1 [-]."""
    transition = follower_transition(parameters, com_height_m, period_s, gravity_mps2)
    return float(np.max(np.abs(np.linalg.eigvals(transition))))


def require_stable(
    par: DcmParameters, com_height_m: float, period_s: float, gravity_mps2: float
) -> None:
    """Raise ParameterError if the gains make the loop unstable on a perfect follower."""
    radius = follower_spectral_radius(par, com_height_m, period_s, gravity_mps2)
    if radius >= 1.0:
        raise ParameterError(
            f"DcmParameters: K_ξ = {par.dcm_gain_per_s:g} 1/s, K_i = "
            f"{par.dcm_integral_gain_per_s:g} 1/s and A_c = {par.com_admittance_per_s2:g} "
            f"1/s² make the loop unstable even on a robot that follows its CoM command "
            f"(spectral radius {radius:.4f} >= 1 at a CoM height of {com_height_m:g} m); "
            f"lower A_c (it must stay below ω² = {gravity_mps2 / com_height_m:.3g} 1/s² "
            f"and ω·K_ξ) or raise K_ξ"
        )
