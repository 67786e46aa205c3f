r"""A structural spring that softens with load, built from native MuJoCo springs.

The law: the compliance grows linearly with the load,

.. math::
    \delta = \frac{\tau}{k_0} + \frac{\tau |\tau|}{k_0 \tau_s}
    \iff
    \tau(\delta) = \operatorname{sign}(\delta) \frac{\tau_s}{2}
        \left(\sqrt{1 + 4 k_0 |\delta| / \tau_s} - 1\right),

with ``k0`` the stiffness at rest [N·m/rad] and ``τ_s`` the softening torque [N·m] (at
``|τ| = τ_s`` the secant stiffness has halved). Its tangent stiffness
``k0 / sqrt(1 + 4 k0 |δ| / τ_s)`` falls monotonically and never reaches zero: the spring
softens with load but never buckles, and it is the same in both directions. This is how a
preloaded structural interface behaves — a bolted flange, a sole pad — whose contact faces
open progressively as the moment grows.

MuJoCo has no such joint spring, but it can be built natively, with no extra degree of
freedom and no Python per step: the law is interpolated linearly between the breakpoints
where the torque reaches ``τ_j = τ_max j / n`` (one "stage" of the interface giving way
per torque step), at the deflections ``δ_j = τ_j / k0 + τ_j² / (k0 τ_s)``. The joint's own
linear spring has the first segment's stiffness ``k_(0)``; each further breakpoint adds a
fixed tendon on the joint whose spring has the dead band ``[-δ_j, δ_j]`` and the (negative)
stiffness ``k_(j) - k_(j-1)``, so past ``±δ_j`` the joint's tangent stiffness drops to
``k_(j)``. Beyond ``τ_max`` the last segment's stiffness continues.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

from zmpkit._validate import positive
from zmpkit.errors import ParameterError

__all__ = ["SofteningSpring", "softening_breakpoints", "softening_segments"]


@dataclass(frozen=True)
class SofteningSpring:
    """The softening law and its piecewise-linear native approximation.

    Attributes:
        stiffness: ``k0``, the tangent stiffness at rest [N·m/rad].
        softening_torque: ``τ_s``, the torque at which the secant stiffness has halved [N·m].
        torque_range: ``τ_max``, the torque up to which the approximation follows the law
            [N·m]; choose it beyond the largest torque expected.
        stages: ``n``, the number of linear segments up to ``τ_max`` [-].
    """

    stiffness: float
    softening_torque: float
    torque_range: float
    stages: int = 6

    def __post_init__(self) -> None:
        positive("SofteningSpring.stiffness", self.stiffness, "N·m/rad")
        positive("SofteningSpring.softening_torque", self.softening_torque, "N·m")
        positive("SofteningSpring.torque_range", self.torque_range, "N·m")
        if not isinstance(self.stages, int) or self.stages < 1:
            raise ParameterError(
                f"SofteningSpring.stages must be an integer >= 1, got {self.stages!r}"
            )

    def law_torque(self, deflection: float) -> float:
        """The smooth law's restoring torque magnitude, signed like the deflection [N·m]."""
        ts = self.softening_torque
        root = math.sqrt(1.0 + 4.0 * self.stiffness * abs(deflection) / ts)
        return math.copysign(0.5 * ts * (root - 1.0), deflection)

    def law_deflection(self, torque: float) -> float:
        """The smooth law's deflection under a torque, ``τ/k0 + τ|τ|/(k0 τ_s)`` [rad]."""
        return (torque + torque * abs(torque) / self.softening_torque) / self.stiffness

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Deflections where the torque reaches ``τ_max j / n``, j = 0 … n [rad]."""
        return softening_breakpoints(
            self.stiffness, self.softening_torque, self.torque_range, self.stages
        )

    @property
    def segment_stiffness(self) -> tuple[float, ...]:
        """Tangent stiffness of each segment, the secant of the law over it [N·m/rad]."""
        return softening_segments(self.breakpoints, self.torque_range, self.stages)

    def torque(self, deflection: float) -> float:
        """The simulated (piecewise-linear) spring torque at a deflection [N·m]."""
        x = abs(deflection)
        total = 0.0
        points = self.breakpoints
        for j, k in enumerate(self.segment_stiffness):
            start = points[j]
            end = points[j + 1] if j + 1 < self.stages else math.inf
            if x <= start:
                break
            total += k * (min(x, end) - start)
        return math.copysign(total, deflection)


def softening_breakpoints(
    stiffness: Any, softening_torque: Any, torque_range: Any, stages: int
) -> tuple[Any, ...]:
    """:attr:`SofteningSpring.breakpoints` [rad].

    The numbers may be numpy arrays (one per candidate of a fit): the same arithmetic,
    element by element (:mod:`zmpkit.sim.effect_fields`).
    """
    out = []
    for j in range(stages + 1):
        torque = torque_range * j / stages
        out.append((torque + torque * abs(torque) / softening_torque) / stiffness)
    return tuple(out)


def softening_segments(
    breakpoints: tuple[Any, ...], torque_range: Any, stages: int
) -> tuple[Any, ...]:
    """:attr:`SofteningSpring.segment_stiffness` of its ``breakpoints`` [N·m/rad] (arrays too)."""
    step = torque_range / stages
    return tuple(step / (b - a) for a, b in itertools.pairwise(breakpoints))
