"""Contact phases of the feet, and what a motion capture measures during them.

All functions take plain arrays (world frame x forward, y left, z up; one row per sample):
which samples a foot stands (from its F-T sensor's vertical force and a contact threshold),
the distance between the feet in double support (the step length), how far a standing foot
slides, and the speed fitted to a trajectory or measured along its path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError

__all__ = [
    "MIN_CONTACT_SAMPLES",
    "FootSlip",
    "contact_phases",
    "double_support_distance",
    "fitted_speed",
    "foot_slip",
    "in_contact",
    "path_speed",
]

MIN_CONTACT_SAMPLES = 5
"""A contact phase shorter than this many samples is a touch, not a stance [-]."""


def in_contact(force_z_in_world_n: NDArray[np.float64], threshold_n: float) -> NDArray[np.bool_]:
    """Whether each foot touches the floor: its vertical force is at least ``threshold_n`` [N].

    The same rule as the ZMP's (:func:`zmpkit.sensors.zmp.zmp_in_world`).
    """
    return np.asarray(force_z_in_world_n) >= threshold_n


def contact_phases(in_contact: NDArray[np.bool_]) -> list[tuple[int, int]]:
    """Runs of contact as (first, last) sample indices, shorter touches dropped."""
    flags = np.concatenate([[False], np.asarray(in_contact, bool), [False]])
    edges = np.flatnonzero(np.diff(flags.astype(int)))
    runs = zip(edges[::2], edges[1::2] - 1, strict=True)
    return [(int(a), int(b)) for a, b in runs if b - a + 1 >= MIN_CONTACT_SAMPLES]


def double_support_distance(
    sole_in_world: NDArray[np.float64],
    in_contact: NDArray[np.bool_],
    heading_rad: NDArray[np.float64] | float = 0.0,
) -> NDArray[np.float64]:
    """Distance between two feet along the walking heading [m] while both touch the floor.

    d = |(p₀ − p₁) · (cos ψ, sin ψ)|: the step length of a walk heading ψ, whatever its
    direction in the world (along world x only when ψ = 0). NaN where a foot is off the floor.

    Args:
        sole_in_world: sole-centre position of the two feet in the world frame [m], shape
            (N, 2, k) with k ≥ 2 (x, y[, z]).
        in_contact: contact of the two feet, shape (N, 2).
        heading_rad: walking heading ψ in the world frame [rad], shape (N,) or a scalar.
    """
    both = np.all(in_contact, axis=1)
    delta = sole_in_world[:, 0, :2] - sole_in_world[:, 1, :2]
    along = delta[:, 0] * np.cos(heading_rad) + delta[:, 1] * np.sin(heading_rad)
    return np.where(both, np.abs(along), np.nan)


@dataclass(frozen=True)
class FootSlip:
    """How far feet slide while they stand.

    Attributes:
        mean_abs_m: mean horizontal displacement of a sole over one stance phase [m].
        mean_x_m: mean x displacement over a stance phase; negative = backwards [m].
        phases: number of stance phases measured.
    """

    mean_abs_m: float
    mean_x_m: float
    phases: int


def foot_slip(
    sole_in_world: NDArray[np.float64], in_contact: NDArray[np.bool_], mask: NDArray[np.bool_]
) -> FootSlip:
    """Sole displacement over each stance phase that lies inside ``mask``.

    Args:
        sole_in_world: sole-centre positions [m], shape (N, F, 3).
        in_contact: contact flags, shape (N, F).
        mask: samples to consider (e.g. the steady walk), shape (N,).
    """
    moves = []
    for foot in range(sole_in_world.shape[1]):
        for a, b in contact_phases(in_contact[:, foot] & mask):
            moves.append(sole_in_world[b, foot, :2] - sole_in_world[a, foot, :2])
    if not moves:
        return FootSlip(0.0, 0.0, 0)
    d = np.array(moves)
    return FootSlip(float(np.mean(np.hypot(d[:, 0], d[:, 1]))), float(np.mean(d[:, 0])), len(d))


def fitted_speed(
    time_s: NDArray[np.float64], x_m: NDArray[np.float64], mask: NDArray[np.bool_]
) -> float:
    """Slope of a straight line fitted to ``x(t)`` over ``mask`` [m/s]."""
    if np.count_nonzero(mask) < 2:
        raise ParameterError("need at least two samples to fit a speed")
    return float(np.polyfit(time_s[mask], x_m[mask], 1)[0])


def path_speed(
    time_s: NDArray[np.float64],
    xy_m: NDArray[np.float64],
    mask: NDArray[np.bool_],
    period_s: float,
) -> float:
    """Speed along the path of a horizontal trajectory, its periodic sway averaged out [m/s].

    :func:`fitted_speed` of x measures the advance along x only: a turning walk's is its
    chord's projection. Here ``xy(t)`` is first averaged over one ``period_s`` (a gait cycle:
    two steps), which removes a sway of that period exactly (a moving average over a whole
    period of a sinusoid is zero), then the path length of the averaged curve is divided by
    its duration: v̄ = Σ‖Δx̄y‖ / (t_end − t_start) over the samples of ``mask`` whose whole
    averaging window lies inside it. Averaging a circle walked at v and turn rate ω over T
    draws it at radius R·sinc(ωT/2) (sinc x = sin x / x), so v̄ = v·sinc(ωT/2); the net turn
    of the averaged path gives ω̂ = |Δψ| / (t_end − t_start) and the result is
    v̄ / sinc(ω̂T/2): v on a circle, the fitted speed on a straight walk. A sway of amplitude
    a across the path leaves a residue of about a·ω²T/(2π) [m/s] on a turning walk.

    Args:
        time_s: sample times, increasing, uniformly spaced [s], shape (N,).
        xy_m: horizontal position [m] (world frame), shape (N, 2).
        mask: the samples to measure over (one contiguous window), shape (N,).
        period_s: the sway's period [s] (> 0).

    Raises:
        ParameterError: on a non-positive period, or a window shorter than two periods.
    """
    if not period_s > 0.0:
        raise ParameterError(f"period_s must be > 0 s, got {period_s!r}")
    t = np.asarray(time_s, dtype=float)[mask]
    xy = np.asarray(xy_m, dtype=float)[mask]
    if t.size < 3 or t[-1] - t[0] < 2.0 * period_s:
        raise ParameterError(
            f"need a window of at least two periods ({2.0 * period_s:g} s) to measure a path "
            f"speed; got {t[-1] - t[0] if t.size else 0.0:g} s"
        )
    dt_s = (t[-1] - t[0]) / (t.size - 1)
    width = max(1, round(period_s / dt_s))
    kernel = np.full(width, 1.0 / width)
    averaged = np.column_stack([np.convolve(xy[:, k], kernel, mode="valid") for k in (0, 1)])
    centres = np.convolve(t, kernel, mode="valid")
    steps = np.diff(averaged, axis=0)
    duration_s = float(centres[-1] - centres[0])
    length_m = float(np.sum(np.linalg.norm(steps, axis=1)))
    moving = np.linalg.norm(steps, axis=1) > 0.0
    if np.count_nonzero(moving) < 2:
        return length_m / duration_s  # standing still: no direction, no turn
    direction = np.unwrap(np.arctan2(steps[moving, 1], steps[moving, 0]))
    turn_rad_s = abs(float(direction[-1] - direction[0])) / duration_s
    half_angle = 0.5 * turn_rad_s * period_s
    return length_m / duration_s / float(np.sinc(half_angle / np.pi))  # np.sinc(x) = sin(πx)/(πx)
