"""Contact phases of the feet, and what a motion capture measures during them.

All functions take plain arrays (world frame x forward, y left, z up; one row per sample):
which samples a foot stands (from its F-T sensor's vertical force and a contact threshold),
the distance between the feet in double support (the step length), how far a standing foot
slides, and the speed fitted to a trajectory.
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
