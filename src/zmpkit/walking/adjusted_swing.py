r"""A swing foot whose landing point and touchdown change while it swings.

The planned swing (:mod:`zmpkit.walking.swing`) blends the sole from lift-off to landing by
the minimum-jerk ``s(τ)`` and lifts it by ``64 h τ^3 (1-τ)^3``. When a step adjustment moves
the landing ``G`` or the touchdown frame ``T'`` mid-swing, the horizontal path is re-planned
from where the sole's target is now, with its velocity and acceleration, as the quintic that
reaches ``G`` at ``T'`` at rest (zero velocity and acceleration):

.. math:: x(t) = \sum_{i=0}^{5} a_i (t - t_0)^i, \quad
    a_0 = x_0,\ a_1 = v_0,\ a_2 = \tfrac{a}{2},\
    a_3 = \frac{20 Δ - 12 v_0 D - 3 a D^2}{2 D^3},\
    a_4 = \frac{-30 Δ + 16 v_0 D + 3 a D^2}{2 D^4},\
    a_5 = \frac{12 Δ - 6 v_0 D - a D^2}{2 D^5}

(``Δ = G - x_0``, ``D = T' - t_0``); with ``v_0 = a = 0`` it is the planned minimum-jerk
blend. The height follows the planned bump of a phase ``φ`` that spreads what is left of it
evenly over the frames left, ``φ_k = φ_{k-1} + (1 - φ_{k-1}) / (T' - k + 1)``: the planned
``φ = (k - k_{lift}) / (T - k_{lift})`` while ``T' = T``, and ``φ = 1`` (the ground) at
``T'``. Time runs in motion frames; a tick's work is scalar arithmetic.
"""

from __future__ import annotations

import numpy as np

__all__ = ["AdjustedSwing"]


class AdjustedSwing:
    """One swing foot's re-planned horizontal quintic and re-timed height (module docstring).

    Args:
        step_height_m: h, the planned swing height [m].

    Attributes:
        x_m, y_m, z_m: the sole centre's target of the last :meth:`advance` [m].
        touchdown_frame: T' [frames].
        goal_m: G, the landing (x, y) [m].
    """

    def __init__(self, step_height_m: float) -> None:
        self.step_height_m = step_height_m
        # per axis, a_0..a_5 [m/frame^i]: in an array, so that a re-plan keeps no new floats
        self._coefficients = np.zeros((2, 6))
        self._rows = (self._coefficients[0], self._coefficients[1])
        self._start = 0.0  # t_0 [frames]
        self.touchdown_frame = 0.0
        self.goal_m = [0.0, 0.0]
        self._phase = 0.0
        self._phase_frame = 0.0
        self.x_m = self.y_m = self.z_m = 0.0

    def start(self, frame: float, x_m: float, y_m: float, goal_x_m: float, goal_y_m: float,
              touchdown_frame: float) -> None:  # fmt: skip
        """Lift off at ``frame`` (the last frame on the ground) from rest at ``(x, y)``."""
        self._phase, self._phase_frame = 0.0, frame
        self.x_m, self.y_m, self.z_m = x_m, y_m, 0.0
        self._plan(frame, x_m, 0.0, 0.0, 0, goal_x_m, touchdown_frame)
        self._plan(frame, y_m, 0.0, 0.0, 1, goal_y_m, touchdown_frame)
        self._start, self.touchdown_frame = frame, touchdown_frame
        self.goal_m[0], self.goal_m[1] = goal_x_m, goal_y_m

    def retarget(
        self, frame: float, goal_x_m: float, goal_y_m: float, touchdown_frame: float
    ) -> None:
        """From ``frame`` on, reach ``(G_x, G_y)`` at ``touchdown_frame`` (> ``frame``)."""
        t = frame - self._start
        self._replan(frame, t, 0, goal_x_m, touchdown_frame)  # no loop: a tick makes one
        self._replan(frame, t, 1, goal_y_m, touchdown_frame)  # loop iterator at most
        self._start, self.touchdown_frame = frame, touchdown_frame
        self.goal_m[0], self.goal_m[1] = goal_x_m, goal_y_m

    def land(self, frame: float, x_m: float, y_m: float) -> None:
        """The sole is down at ``(x, y)`` [m] from ``frame`` on (where it was measured)."""
        self.touchdown_frame = frame
        self.goal_m[0], self.goal_m[1] = x_m, y_m

    def _replan(self, frame: float, t: float, axis: int, goal: float, touchdown: float) -> None:
        """One axis's quintic from its state ``t`` frames into the current one."""
        c = self._rows[axis]
        a1, a2, a3, a4, a5 = c.item(1), c.item(2), c.item(3), c.item(4), c.item(5)
        x = c.item(0) + t * (a1 + t * (a2 + t * (a3 + t * (a4 + t * a5))))
        v = a1 + t * (2.0 * a2 + t * (3.0 * a3 + t * (4.0 * a4 + t * 5.0 * a5)))
        a = 2.0 * a2 + t * (6.0 * a3 + t * (12.0 * a4 + t * 20.0 * a5))
        self._plan(frame, x, v, a, axis, goal, touchdown)

    def _plan(self, frame: float, x: float, v: float, a: float, axis: int, goal: float,
              touchdown_frame: float) -> None:  # fmt: skip
        d = touchdown_frame - frame
        c = self._rows[axis]
        delta = goal - x
        c[0], c[1], c[2] = x, v, 0.5 * a
        c[3] = (20.0 * delta - 12.0 * v * d - 3.0 * a * d * d) / (2.0 * d * d * d)
        c[4] = (-30.0 * delta + 16.0 * v * d + 3.0 * a * d * d) / (2.0 * d * d * d * d)
        c[5] = (12.0 * delta - 6.0 * v * d - a * d * d) / (2.0 * d * d * d * d * d)

    def advance(self, frame: float) -> None:
        """The target of ``frame`` (frames in order, one call each): ``x_m``, ``y_m``, ``z_m``."""
        if frame >= self.touchdown_frame:
            self.x_m, self.y_m, self.z_m = self.goal_m[0], self.goal_m[1], 0.0
            return
        t = frame - self._start
        self.x_m = _position(self._rows[0], t)
        self.y_m = _position(self._rows[1], t)
        if frame > self._phase_frame:
            self._phase += (1.0 - self._phase) / (self.touchdown_frame - self._phase_frame)
            self._phase_frame = frame
        phase = self._phase
        bump = phase * (1.0 - phase)
        self.z_m = 64.0 * self.step_height_m * bump * bump * bump


def _position(c: np.ndarray, t: float) -> float:
    """``Σ a_i t^i`` of one axis's quintic (Horner) [m]."""
    a4, a5 = c.item(4), c.item(5)
    return c.item(0) + t * (c.item(1) + t * (c.item(2) + t * (c.item(3) + t * (a4 + t * a5))))
