r"""The ZMP reference of a walk whose steps move: rewritten in place, one step at a time.

The linear reference (:mod:`zmpkit.walking.zmp_reference`) holds the ZMP on the stance sole
``S`` and moves it to the landing over the double support ``T_d`` from the touchdown ``T``.
A step that lands at ``G`` at ``T'`` instead takes the transfer with it, and every later
footstep moves by the landing's offset ``o = G - U`` (``U`` the planned landing):

.. math:: p(t) = S + (G - S)\, r(t - T') \quad (\text{the step's span}), \qquad
    p(t) = p^{plan}(t) + o \quad (\text{after it}),

``r`` the unit transfer (0 before, linear over ``T_d``, 1 after). The arrays are changed by
what the new landing changes (so another online change of the reference, such as paper B's
Algorithm 2, is kept), through views made with the walk: a rewrite runs ufuncs only.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from zmpkit.walking.planned_steps import PlannedStep

__all__ = ["ReplannedZmpReference"]


class _StepViews:
    """What re-planning one step's reference writes (made with the walk)."""

    def __init__(self, reference_by_axis: list[NDArray[np.float64]], first: int, end: int) -> None:
        self.frames = np.arange(first, end, dtype=np.float64)
        self.ramp = np.zeros(end - first)
        self.change = np.zeros(end - first)
        self.new = np.zeros((2, end - first))
        self.old = np.zeros((2, end - first))
        self.new_rows = (self.new[0], self.new[1])
        self.old_rows = (self.old[0], self.old[1])
        self.segments = tuple(r[first:end] for r in reference_by_axis)
        self.tails = tuple(r[end:] for r in reference_by_axis)


class ReplannedZmpReference:
    """Rewrites a ZMP reference as its steps move (module docstring).

    Args:
        reference_by_axis: the reference of every motion frame, one writable array per axis
            (x, y) [m] (a preview controller's, padded past the walk's end).
        steps: the plan's steps.
        double_support_frames: T_d in motion frames [-] (> 0).
    """

    def __init__(
        self,
        reference_by_axis: list[NDArray[np.float64]],
        steps: tuple[PlannedStep, ...],
        double_support_frames: float,
    ) -> None:
        self._t_d_frames = double_support_frames
        size = reference_by_axis[0].size
        self._views = [
            _StepViews(
                reference_by_axis,
                s.lift,
                min(math.ceil(s.touchdown + double_support_frames) + 1, size),
            )
            for s in steps
        ]
        self._scalar = np.zeros(())  # a ufunc's scalar, written in place
        self._zero, self._one = np.zeros(()), np.ones(())
        self._tail_offset = [0.0, 0.0]

    def begin(
        self, j: int, start_x: float, start_y: float, goal_x: float, goal_y: float,
        touchdown: float, offset_x: float, offset_y: float,
    ) -> None:  # fmt: skip
        """Step ``j`` lifts off: the reference holds its transfer from ``start`` to ``goal``.

        Args:
            j: the step [-].
            start_x: the stance sole S (x) [m].
            start_y: the same (y) [m].
            goal_x: the landing G (x) [m].
            goal_y: the same (y) [m].
            touchdown: T [frames].
            offset_x: the offset o the reference after this step carries (x) [m].
            offset_y: the same (y) [m].
        """
        views = self._views[j]
        self._shape(views, views.old_rows, start_x, start_y, goal_x, goal_y, touchdown)
        self._tail_offset[0], self._tail_offset[1] = offset_x, offset_y

    def replan(
        self, j: int, start_x: float, start_y: float, goal_x: float, goal_y: float,
        touchdown: float, offset_x: float, offset_y: float,
    ) -> None:  # fmt: skip
        """Step ``j`` lands at ``goal`` at ``touchdown``: rewrite its transfer and the rest."""
        views = self._views[j]
        self._shape(views, views.new_rows, start_x, start_y, goal_x, goal_y, touchdown)
        self._move(0, offset_x, views)  # unrolled: a tick holds one loop iterator at most
        self._move(1, offset_y, views)
        np.copyto(views.old, views.new)

    def _shape(
        self, views: _StepViews, rows: tuple[NDArray[np.float64], ...], start_x: float,
        start_y: float, goal_x: float, goal_y: float, touchdown: float,
    ) -> None:  # fmt: skip
        """``S + (G - S) r(t - T')`` over the step's transfer, into ``rows`` (x, y) [m]."""
        scalar = self._scalar
        scalar[()] = touchdown
        np.subtract(views.frames, scalar, out=views.ramp)
        scalar[()] = 1.0 / self._t_d_frames
        np.multiply(views.ramp, scalar, out=views.ramp)
        np.maximum(views.ramp, self._zero, out=views.ramp)
        np.minimum(views.ramp, self._one, out=views.ramp)
        self._ramp_to(start_x, goal_x, views, rows[0])
        self._ramp_to(start_y, goal_y, views, rows[1])

    def _ramp_to(
        self, start: float, goal: float, views: _StepViews, row: NDArray[np.float64]
    ) -> None:
        """``start + (goal - start) r`` into ``row`` [m] (``r`` in ``views.ramp``)."""
        scalar = self._scalar
        scalar[()] = goal - start
        np.multiply(views.ramp, scalar, out=row)
        scalar[()] = start
        np.add(row, scalar, out=row)

    def _move(self, axis: int, offset: float, views: _StepViews) -> None:
        """One axis: the transfer's change, and the rest of the walk by the new offset."""
        np.subtract(views.new_rows[axis], views.old_rows[axis], out=views.change)
        np.add(views.segments[axis], views.change, out=views.segments[axis])
        self._scalar[()] = offset - self._tail_offset[axis]
        np.add(views.tails[axis], self._scalar, out=views.tails[axis])
        self._tail_offset[axis] = offset
