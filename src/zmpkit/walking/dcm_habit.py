r"""The walk's own repeated DCM deviation, learned swing by swing (step adjustment's baseline).

A walking robot's DCM deviates from the plan's in the same way step after step (the built-in
walker rocks 3 cm forward in mid-swing). The step adjustment
(:mod:`zmpkit.walking.step_adjustment`) reacts to the rest: at frame ``i`` of a swing of
foot ``f``, the habit ``h_{f,i}`` is the exponentially weighted mean of the earlier swings'
errors,

.. math:: h_{f,i} \leftarrow h_{f,i} + α\,(e - h_{f,i}),

learned only while no step is being adjusted nor was over the last two swings.
"""

from __future__ import annotations

__all__ = ["DcmHabit"]


class DcmHabit:
    """The repeated DCM error per foot, axis and frame of the swing (module docstring).

    Args:
        feet: how many feet [-].
        swing_frames: the longest swing [frames].
        rate: α [-].
    """

    def __init__(self, feet: int, swing_frames: int, rate: float) -> None:
        self._rate = rate
        self._habit = [[[0.0] * swing_frames for _ in range(2)] for _ in range(feet)]
        self._quiet = 0  # swings since the last adjusted one

    def begin(self, last_adjusted: bool) -> None:
        """A swing lifts off; ``last_adjusted``: whether the previous swing was adjusted."""
        self._quiet = 0 if last_adjusted else self._quiet + 1

    def remove(
        self, foot: int, i: int, ex: float, ey: float, adjusting: bool
    ) -> tuple[float, float]:
        """The error ``e`` [m] less the habit of ``foot`` at frame ``i`` of its swing.

        ``adjusting``: a step is being adjusted (the habit is then not learned).
        """
        habit, rate = self._habit[foot], self._rate
        hx, hy = habit[0][i], habit[1][i]
        if not adjusting and self._quiet >= 2:
            habit[0][i], habit[1][i] = hx + rate * (ex - hx), hy + rate * (ey - hy)
        return ex - hx, ey - hy
