r"""Two steps that capture the DCM when one cannot: the N = 2 capture of the LIPM, in closed form.

With ``ω = √(g/z_c)`` the DCM ``ξ`` of the LIPM obeys ``ξ̇ = ω (ξ - p)``. Per axis of the
stance foot's frame, let ``x_0 = ξ - p_0`` be the DCM relative to the stance sole's centre
now, ``σ_1 = e^{ω τ_1}`` for the time ``τ_1`` [s] to the first touchdown and
``σ_2 = e^{ω T_2}`` for the second step's duration ``T_2`` [s]. Each stance ankle may hold its
CoP up to ``m`` off its sole's centre (a dead band); the first landing lies ``u_1 = p_1 - p_0``
from the stance sole and the second ``u_2 = p_2 - p_1`` from the first. The DCM relative to the
first landing at its touchdown is, with the CoP at its best ``|δ| ≤ m``,

.. math:: r_1 = x_0 σ_1 - δ_0 (σ_1 - 1) - u_1,

and relative to the first landing at the second touchdown ``r_1 σ_2 - δ_1 (σ_2 - 1)``. The
second step captures when it lands within ``l`` (the new sole's landing margin) of that DCM
and inside its box ``a_2 ≤ u_2 ≤ b_2``; the first lies in ``a_1 ≤ u_1 ≤ b_1``. Both are
affine in ``u_1``, so the first landings that capture at the second form the interval

.. math:: u_1 \in \Big[D_1 - \frac{b_2 + l + m(σ_2 - 1)}{σ_2},\;
          D_1 - \frac{a_2 - l - m(σ_2 - 1)}{σ_2}\Big] \cap [a_1, b_1],
          \qquad D_1 = x_0 σ_1 \pm m (σ_1 - 1),

(``δ_0``, ``δ_1`` chosen to bring the DCM towards the landings that capture). The first landing
nearest the plan's (``u_1^{plan}``) within it is chosen; the second then lands at the captured
DCM, clipped to its box. When the interval is empty no two steps of this reach capture: the
first landing goes to the end of its box nearest the interval and the DCM error that is left is
reported (Koolen et al. 2012's N-step capturability: with ``a_i = -R``, ``b_i = R``, ``m = l =
0`` the DCM is two-step capturable iff ``|x_0| σ_1 ≤ R (1 + 1/σ_2)``). Scalar arithmetic only
(no arrays, no loops; only the returned tuple, as with
:func:`~zmpkit.walking.capture_step.solve_capture`); :func:`two_step_capture` wraps both axes
in a result.

What a second step buys: ``R/σ_2`` of capturable DCM. On the built-in walker (``z_c`` 0.25 m,
ω 6.26 1/s, a reach of 0.25 m) a 0.5 s second step adds 1.1 cm (0.261 m against 0.25 m; the
infinite-step limit ``R σ_2/(σ_2 - 1)`` is the same 0.261 m); shortened to 0.25 s it adds
5.2 cm (0.302 m), to 0.2 s 7.1 cm. A second step helps only with its timing adapted.

Called by the walk with :attr:`~.StepAdjustmentParameters.two_step` (opt-in): a triggered
step lands, at its planned touchdown, nearest the plan where the next step captures on the
plan's timing (:func:`solve_two_step_into`, the tick's form). The 20 N pushes along -y (over
the stance sole) are beyond it on the built-in walker: with the walk's own reach boxes, the
estimated DCM 4.2 cm beyond the right sole's centre once the push is in (4.25 s, 20 N -y at
a quarter of the seventh step) leaves 0.10 m uncaptured even with the first step at its
earliest and the second shortened to 0.2 s (0.21 m at 0.25 s), the ankle holding the CoP at
the sole's edge throughout; only at 4.20 s, mid-push, would a second step of 0.25 s
capture. (An earlier note had these falls touching down mid-swing: the "touchdown" was the
contact of a foot that never left the ground, :mod:`~zmpkit.walking.measured_footholds`.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.scalar_limits import clip

__all__ = ["TwoStepCapture", "solve_two_step", "solve_two_step_into", "two_step_capture"]


def _dead_band(value: float, band: float) -> float:
    """``value`` moved towards zero by ``band`` >= 0, stopping at zero [m]."""
    if value > band:
        return value - band
    if value < -band:
        return value + band
    return 0.0


def _towards(value: float, lo: float, hi: float, band: float) -> float:
    """``value`` moved towards ``[lo, hi]`` by at most ``band`` >= 0 (the CoP's share) [m]."""
    if value > hi:
        moved = value - band
        return hi if hi > moved else moved
    if value < lo:
        moved = value + band
        return lo if lo < moved else moved
    return value


def solve_two_step(
    dcm_m: float,
    sigma_first: float,
    sigma_second: float,
    planned_first_m: float,
    lo_first_m: float,
    hi_first_m: float,
    lo_second_m: float,
    hi_second_m: float,
    cop_margin_m: float,
    landing_margin_m: float,
) -> tuple[float, float, float]:
    """One axis of the module docstring's two-step capture (scalars only).

    Args: ``dcm_m`` x_0 [m]; ``sigma_first`` σ_1 >= 1, ``sigma_second`` σ_2 >= 1 [-];
    ``planned_first_m`` u_1^{plan} [m]; the boxes ``[lo, hi]`` of u_1 and u_2 [m]; ``cop_margin_m``
    m and ``landing_margin_m`` l [m]. Returns ``(u_1, u_2, left)``: the landings [m] and the DCM
    error the second step leaves outside its landing margin (0 when it captures) [m].
    """
    out = [0.0, 0.0, 0.0]
    solve_two_step_into(
        out, dcm_m, sigma_first, sigma_second, planned_first_m, lo_first_m, hi_first_m,
        lo_second_m, hi_second_m, cop_margin_m, landing_margin_m,
    )  # fmt: skip
    return out[0], out[1], out[2]


def solve_two_step_into(
    out: list[float],
    dcm_m: float,
    sigma_first: float,
    sigma_second: float,
    planned_first_m: float,
    lo_first_m: float,
    hi_first_m: float,
    lo_second_m: float,
    hi_second_m: float,
    cop_margin_m: float,
    landing_margin_m: float,
) -> None:
    """:func:`solve_two_step` (its arguments) written into ``out[0:3] = (u_1, u_2, left)``.

    No tuple is built: a control tick's form.
    """
    band_first = cop_margin_m * (sigma_first - 1.0)
    band_second = cop_margin_m * (sigma_second - 1.0)
    reach_lo = lo_second_m - landing_margin_m - band_second  # of r_1 σ_2 [m]
    reach_hi = hi_second_m + landing_margin_m + band_second
    base = dcm_m * sigma_first
    lo = base - band_first - reach_hi / sigma_second
    hi = base + band_first - reach_lo / sigma_second
    captured = lo <= hi_first_m and hi >= lo_first_m
    if lo > hi_first_m:  # no first landing in the box captures at the second
        first = hi_first_m
    elif hi < lo_first_m:
        first = lo_first_m
    else:
        low = lo if lo > lo_first_m else lo_first_m  # (no min/max: they allocate)
        first = clip(planned_first_m, low, hi if hi < hi_first_m else hi_first_m)
    at_first = _towards(
        base, first + reach_lo / sigma_second, first + reach_hi / sigma_second, band_first
    )
    wanted = _towards((at_first - first) * sigma_second, lo_second_m, hi_second_m, band_second)
    second = clip(wanted, lo_second_m, hi_second_m)
    left = 0.0 if captured else abs(_dead_band(wanted - second, landing_margin_m))
    out[0], out[1], out[2] = first, second, left


@dataclass(frozen=True)
class TwoStepCapture:
    """Two capture steps (module docstring), in the stance foot's frame.

    Attributes:
        first_m: u_1, the first landing relative to the stance sole (along, across) [m].
        second_m: u_2, the second landing relative to the first (along, across) [m].
        captured: whether the DCM is captured at the second step within the limits.
        dcm_error_left_m: the DCM error the two steps leave (largest axis; 0 if captured) [m].
    """

    first_m: tuple[float, float]
    second_m: tuple[float, float]
    captured: bool
    dcm_error_left_m: float


def two_step_capture(
    dcm_m: tuple[float, float],
    omega_per_s: float,
    first_remaining_s: float,
    second_duration_s: float,
    planned_first_m: tuple[float, float],
    first_box_m: tuple[float, float, float, float],
    second_box_m: tuple[float, float, float, float],
    cop_margin_m: tuple[float, float] = (0.0, 0.0),
    landing_margin_m: tuple[float, float] = (0.0, 0.0),
) -> TwoStepCapture:
    """Both axes of :func:`solve_two_step`, inputs checked.

    Args:
        dcm_m: x_0 = ξ - p_0, (along, across) the stance sole [m].
        omega_per_s: ω [1/s].
        first_remaining_s: τ_1, time to the first touchdown [s].
        second_duration_s: T_2, the second step's duration (lift-off to touchdown plus the
            double support it keeps) [s].
        planned_first_m: u_1^{plan}, the plan's first landing (along, across) [m].
        first_box_m: (lo_x, hi_x, lo_y, hi_y) of u_1, from the legs' reach and the
            no-crossing limit (:mod:`zmpkit.walking.step_reach`) [m].
        second_box_m: the same of u_2, relative to the first landing [m].
        cop_margin_m: m, (along, across) [m].
        landing_margin_m: l, (along, across) [m].
    """
    omega = _validate.positive("omega_per_s", omega_per_s, "1/s")
    tau1 = _validate.non_negative("first_remaining_s", first_remaining_s, "s")
    t2 = _validate.non_negative("second_duration_s", second_duration_s, "s")
    for name, box in (("first_box_m", first_box_m), ("second_box_m", second_box_m)):
        if not (box[0] <= box[1] and box[2] <= box[3]):
            raise ParameterError(
                f"{name} must be (lo_x, hi_x, lo_y, hi_y) with lo <= hi; got {box}"
            )
    s1, s2 = math.exp(omega * tau1), math.exp(omega * t2)
    fx, sx, lx = solve_two_step(
        dcm_m[0], s1, s2, planned_first_m[0], first_box_m[0], first_box_m[1],
        second_box_m[0], second_box_m[1], cop_margin_m[0], landing_margin_m[0],
    )  # fmt: skip
    fy, sy, ly = solve_two_step(
        dcm_m[1], s1, s2, planned_first_m[1], first_box_m[2], first_box_m[3],
        second_box_m[2], second_box_m[3], cop_margin_m[1], landing_margin_m[1],
    )  # fmt: skip
    left = max(lx, ly)
    return TwoStepCapture((fx, fy), (sx, sy), left == 0.0, left)
