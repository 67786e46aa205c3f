r"""Where and when the swing foot must land to capture the DCM: the capture step, in closed form.

With ``ω = √(g/z_c)`` the divergent component of motion ``ξ = c + ċ/ω`` of the LIPM obeys
``ξ̇ = ω (ξ - p)``: while the stance foot holds the ZMP at ``p``, a DCM ``τ`` [s] before
touchdown reaches

.. math:: ξ(T) = p + (ξ - p)\, e^{ω τ}.

The plan put the DCM at ``ξ^{ref}`` now and the stance ZMP at ``p^{ref}`` (the sole's
centre); with ``e = ξ - ξ^{ref}`` (the DCM error), ``b = ξ^{ref} - p^{ref}`` and
``σ = e^{ωτ}`` for the (adapted) remaining time, ``σ_0`` for the planned one, the DCM at
touchdown deviates from the plan's by

.. math:: D(σ) = e\,σ + b\,(σ - σ_0) - δ_p\,(σ - 1),

where ``δ_p`` is what the stance foot's CoP may still shift (``|δ_p| ≤ m``, the ankle's
share; chosen to make ``|D|`` least, a dead band ``m (σ - 1)``). After touchdown the plan
moves the ZMP from the stance sole to the new one in a straight line over the double
support ``T_d``; a landing ``Δ`` away from the plan's restores the plan's DCM relative to the
new sole at the end of that transfer when

.. math:: Δ = \frac{D}{κ}, \qquad κ = \frac{1 - e^{-ω T_d}}{ω T_d}

(``κ = 1`` without double support: then ``Δ = e σ`` for a planned touchdown, the DCM error
carried to touchdown). The landing must stay in the box the robot's legs reach
(``lo ≤ Δ ≤ hi`` per axis of the stance foot's frame, :mod:`zmpkit.walking.step_reach`) and
the touchdown no earlier than ``σ_min`` allows. The choice is lexicographic, the solution of
the small QP "capture, then keep the timing, then keep the landing":

1. each bound ``lo_i ≤ Δ_i(σ) ≤ hi_i`` is affine in ``σ`` (the dead band only widens it), so
   the touchdowns that capture form an interval ``[σ_a, σ_b]``; within ``[σ_min, σ_0]``
   the latest (``σ_b``: the least change of timing) is taken, with the least ``|Δ|``;
2. if none captures, the ``σ`` that leaves the least DCM error outside the box (a convex
   piecewise-linear function: its minimum lies at an end or at one of the bounds' roots) is
   taken, the landing clipped to the box, and the step is reported as not capturing.

Lengthening a step never helps here: the nominal landing (``Δ = 0``) lies in the box, and
``Δ`` grows with ``σ``. Everything is scalar arithmetic (a control tick's computation
allocates nothing); :func:`capture_step` wraps it in a result for use off the tick.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.walking.scalar_limits import clip

__all__ = [
    "CaptureStep",
    "capture_step",
    "double_support_factor",
    "solve_capture",
    "transfer_dcm",
    "transfer_zmp",
]

_NONE = -1.0  # an absent bound on σ


def double_support_factor(omega_per_s: float, double_support_s: float) -> float:
    """κ = (1 - e^{-ω T_d}) / (ω T_d) of the module docstring [-]; 1 without double support."""
    x = omega_per_s * double_support_s
    return 1.0 if x <= 0.0 else -math.expm1(-x) / x


def transfer_zmp(double_support_s: float, ahead_s: float) -> float:
    """The ZMP of a unit transfer that starts ``ahead_s`` from now [-]: 0 before, 1 after.

    The transfer moves the ZMP at constant speed over ``T_d``; ``ahead_s < 0``: it began.
    """
    if ahead_s >= 0.0:
        return 0.0
    if -ahead_s >= double_support_s:
        return 1.0
    return -ahead_s / double_support_s


def transfer_dcm(omega_per_s: float, double_support_s: float, ahead_s: float) -> float:
    r"""The DCM of a unit ZMP transfer that starts ``ahead_s`` from now [-].

    The bounded DCM of a ZMP path ``p`` is ``ξ(t) = ω ∫_t^∞ e^{-ω(s - t)} p(s) ds``; for the
    unit ramp of :func:`transfer_zmp` (``T_d`` long) it is ``κ e^{-ω a}`` while it lies
    ``a ≥ 0`` ahead, 1 once it is over, and within it, ``u`` into it, ``L = T_d - u``,
    ``E = e^{-ω L}``:

    .. math:: ξ = \frac{u (1 - E) + (1 - E (1 + ω L))/ω}{T_d} + E.
    """
    omega, t_d = omega_per_s, double_support_s
    if ahead_s >= 0.0:
        return double_support_factor(omega, t_d) * math.exp(-omega * ahead_s)
    inside = -ahead_s
    if inside >= t_d:
        return 1.0
    rest = t_d - inside
    fade = math.exp(-omega * rest)
    return (inside * (1.0 - fade) + (1.0 - fade * (1.0 + omega * rest)) / omega) / t_d + fade


def _required(
    a: float, b_sigma0: float, margin: float, landing: float, sigma: float, kappa: float
) -> float:
    """Δ(σ) = deadband(a σ - b σ_0, m (σ - 1) + l) / κ: the landing shift that captures [m]."""
    d = a * sigma - b_sigma0
    band = margin * (sigma - 1.0) + landing
    if d > band:
        return (d - band) / kappa
    if d < -band:
        return (d + band) / kappa
    return 0.0


def _excess(value: float, lo: float, hi: float) -> float:
    """How far ``value`` lies outside ``[lo, hi]`` [m]."""
    return value - hi if value > hi else (lo - value if value < lo else 0.0)


def _upper(upper: float, c: float, d: float) -> float:
    """The largest σ of ``[.., upper]`` with ``c σ <= d`` (-inf: none)."""
    if c > 0.0:
        root = d / c
        return root if root < upper else upper
    return upper if c < 0.0 or d >= 0.0 else -math.inf


def _lower(lower: float, c: float, d: float) -> float:
    """The least σ of ``[lower, ..]`` with ``c σ <= d`` (inf: none)."""
    if c < 0.0:
        root = d / c
        return root if root > lower else lower
    return lower if c > 0.0 or d >= 0.0 else math.inf


def _root(c: float, d: float) -> float:
    """σ at which ``c σ = d``, or -1 (none)."""
    return d / c if c != 0.0 else _NONE


def solve_capture(
    error_x: float,
    error_y: float,
    offset_x: float,
    offset_y: float,
    sigma_plan: float,
    sigma_min: float,
    kappa: float,
    margin_x: float,
    margin_y: float,
    landing_x: float,
    landing_y: float,
    lo_x: float,
    hi_x: float,
    lo_y: float,
    hi_y: float,
) -> tuple[float, float, float, float]:
    """The capture step of the module docstring, in the stance foot's frame (scalars only).

    Arguments, ``_x`` along the stance foot and ``_y`` across it: ``error`` e, ``offset`` b,
    ``margin`` m, ``landing`` l (how far off its centre the new sole may take the DCM),
    ``lo`` <= 0 and ``hi`` >= 0 the least and the largest shift, all [m]; ``sigma_plan``
    σ_0 = e^{ω τ_0} >= 1 of the planned remaining time and ``sigma_min`` e^{ω τ_min} in
    [1, σ_0] of the earliest touchdown [-]; ``kappa`` κ of the double support, in (0, 1]
    [-]. Each bound is one affine ``c σ ≤ d`` (module docstring, 1). Returns ``(σ, Δ_x, Δ_y,
    left)``: the chosen σ [-], the landing shift within the box [m] and the DCM error the
    step leaves outside the box, times κ (0 when it captures) [m]. Written without tuples or
    loops (a control tick makes no objects of its own).
    """
    ax, ay = error_x + offset_x, error_y + offset_y
    bx, by = offset_x * sigma_plan, offset_y * sigma_plan
    c1, d1 = ax - margin_x, kappa * hi_x + bx - margin_x + landing_x
    c2, d2 = -(ax + margin_x), -(kappa * lo_x + bx + margin_x - landing_x)
    c3, d3 = ay - margin_y, kappa * hi_y + by - margin_y + landing_y
    c4, d4 = -(ay + margin_y), -(kappa * lo_y + by + margin_y - landing_y)
    upper = _upper(_upper(_upper(_upper(sigma_plan, c1, d1), c2, d2), c3, d3), c4, d4)
    lower = _lower(_lower(_lower(_lower(sigma_min, c1, d1), c2, d2), c3, d3), c4, d4)
    if lower <= upper:
        dx = _required(ax, bx, margin_x, landing_x, upper, kappa)
        dy = _required(ay, by, margin_y, landing_y, upper, kappa)
        return upper, clip(dx, lo_x, hi_x), clip(dy, lo_y, hi_y), 0.0
    # No σ captures: the least total excess, a convex piecewise-linear function of σ, lies at
    # an end or at a root; ties go to the later touchdown.
    best, least = sigma_plan, math.inf
    margins = (margin_x, margin_y, landing_x, landing_y)
    box, bounds = (lo_x, hi_x, lo_y, hi_y), (sigma_min, sigma_plan)
    best, least = _better(best, least, sigma_plan, ax, bx, ay, by, kappa, margins, box, bounds)
    best, least = _better(best, least, sigma_min, ax, bx, ay, by, kappa, margins, box, bounds)
    root = _root(c1, d1)  # unrolled: no loop, no tuple of the bounds
    best, least = _better(best, least, root, ax, bx, ay, by, kappa, margins, box, bounds)
    root = _root(c2, d2)
    best, least = _better(best, least, root, ax, bx, ay, by, kappa, margins, box, bounds)
    root = _root(c3, d3)
    best, least = _better(best, least, root, ax, bx, ay, by, kappa, margins, box, bounds)
    root = _root(c4, d4)
    best, least = _better(best, least, root, ax, bx, ay, by, kappa, margins, box, bounds)
    dx = _required(ax, bx, margin_x, landing_x, best, kappa)
    dy = _required(ay, by, margin_y, landing_y, best, kappa)
    return best, clip(dx, lo_x, hi_x), clip(dy, lo_y, hi_y), kappa * max(least, 1e-9)


def _better(
    best: float, least: float, sigma: float, ax: float, bx: float, ay: float, by: float,
    kappa: float, margins: tuple[float, float, float, float],
    box: tuple[float, float, float, float], bounds: tuple[float, float],
) -> tuple[float, float]:  # fmt: skip
    """``(σ, excess)``: the best so far, or ``sigma`` if it lies in ``bounds`` and leaves less."""
    if not bounds[0] <= sigma <= bounds[1]:
        return best, least
    mx, my, lx, ly = margins
    lo_x, hi_x, lo_y, hi_y = box
    left = _excess(_required(ax, bx, mx, lx, sigma, kappa), lo_x, hi_x)
    left += _excess(_required(ay, by, my, ly, sigma, kappa), lo_y, hi_y)
    if left < least - 1e-12 or (left < least + 1e-12 and sigma > best):
        return sigma, left
    return best, least


@dataclass(frozen=True)
class CaptureStep:
    """A capture step (module docstring), in the stance foot's frame.

    Attributes:
        remaining_s: time left to the chosen touchdown [s].
        shift_m: the landing's shift from the planned landing, (along, across) [m].
        captured: whether the step captures the DCM within the limits.
        dcm_error_left_m: the DCM error at the end of the transfer that the step cannot
            remove (0 when it captures) [m].
    """

    remaining_s: float
    shift_m: tuple[float, float]
    captured: bool
    dcm_error_left_m: float


def capture_step(
    dcm_error_m: tuple[float, float],
    dcm_offset_m: tuple[float, float],
    omega_per_s: float,
    planned_remaining_s: float,
    earliest_remaining_s: float,
    double_support_s: float,
    cop_margin_m: tuple[float, float],
    shift_box_m: tuple[float, float, float, float],
    landing_margin_m: tuple[float, float] = (0.0, 0.0),
) -> CaptureStep:
    """The capture step for one DCM error (the tick's :func:`solve_capture`, checked inputs).

    Args:
        dcm_error_m: e = ξ - ξ^{ref}, (along, across) the stance foot [m].
        dcm_offset_m: b = ξ^{ref} - p^{ref}, (along, across) [m].
        omega_per_s: ω [1/s].
        planned_remaining_s: τ_0, the time to the planned touchdown [s].
        earliest_remaining_s: τ_min, the time to the earliest touchdown allowed [s].
        double_support_s: T_d, the plan's transfer after touchdown [s].
        cop_margin_m: m, the CoP shift left to the stance ankle, (along, across) [m].
        shift_box_m: (lo_x, hi_x, lo_y, hi_y), the landing shifts the legs reach [m]
            (each lo <= 0 <= hi: the planned landing is reachable).
        landing_margin_m: l, how far off its centre the new sole may take the DCM (along,
            across) [m].
    """
    omega = _validate.positive("omega_per_s", omega_per_s, "1/s")
    tau0 = _validate.non_negative("planned_remaining_s", planned_remaining_s, "s")
    tau_min = _validate.in_range("earliest_remaining_s", earliest_remaining_s, 0.0, tau0, "s")
    t_d = _validate.non_negative("double_support_s", double_support_s, "s")
    lo_x, hi_x, lo_y, hi_y = (_validate.finite("shift_box_m", v) for v in shift_box_m)
    if not (lo_x <= 0.0 <= hi_x and lo_y <= 0.0 <= hi_y):
        raise ParameterError(
            f"shift_box_m must hold the planned landing (lo <= 0 <= hi per axis); got {shift_box_m}"
        )
    mx, my = (_validate.non_negative("cop_margin_m", v, "m") for v in cop_margin_m)
    lx, ly = (_validate.non_negative("landing_margin_m", v, "m") for v in landing_margin_m)
    sigma0, sigma_min = math.exp(omega * tau0), math.exp(omega * tau_min)
    sigma, dx, dy, left = solve_capture(
        *dcm_error_m, *dcm_offset_m, sigma0, sigma_min, double_support_factor(omega, t_d),
        mx, my, lx, ly, lo_x, hi_x, lo_y, hi_y,
    )  # fmt: skip
    return CaptureStep(math.log(sigma) / omega, (dx, dy), left == 0.0, left)
