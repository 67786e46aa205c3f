"""What a walk's step adjustment did: the steps it moved, and those it could not make capture.

A :class:`StepEvent` is kept for every step the adjustment moved
(:mod:`zmpkit.walking.step_adjustment`); the walk's record, summary and report carry them, so
that a push no admissible step could catch is said, not hidden (:data:`NOT_CAPTURED`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["NOT_CAPTURED", "StepEvent", "StepLog"]

NOT_CAPTURED = "no admissible step captures the DCM"
"""The event of a step that could not capture the DCM within the legs' limits."""


@dataclass(frozen=True)
class StepEvent:
    """A step the walk adjusted.

    Attributes:
        time_s: when the adjustment began [s].
        step: the footstep's index [-].
        side: the swing foot.
        dcm_error_m: the DCM error that triggered it (x, y), world frame [m].
        shift_m: where it landed against the plan's landing (x, y), world frame [m]; (0, 0)
            if the walk ended (a fall) before it landed.
        shortened_s: how much earlier than planned it touched down [s] (0 if it did not).
        captured: whether a step within the limits captured the DCM.
        dcm_error_left_m: the DCM error the step could not remove [m] (0: captured).
    """

    time_s: float
    step: int
    side: str
    dcm_error_m: tuple[float, float]
    shift_m: tuple[float, float]
    shortened_s: float
    captured: bool
    dcm_error_left_m: float

    @property
    def kind(self) -> str:
        """``step adjusted``, or :data:`NOT_CAPTURED`."""
        return "step adjusted" if self.captured else NOT_CAPTURED


class StepLog:
    """What the step adjustment did to each step, written by the tick, read as events.

    Args:
        steps: how many steps the walk has [-].
        sides: each step's swing foot.
        period_s: the control period [s].

    Attributes (per step, written in place by the tick):
        trigger_frame: the frame the adjustment began, -1 none [-].
        trigger_error: the DCM error that triggered it (x, y) [m], shape (M, 2).
        left: the DCM error it could not remove [m], shape (M,).
        shift: where it landed against the plan (x, y) [m], shape (M, 2).
        landed_at: how much earlier than planned it touched down [s], shape (M,).
    """

    def __init__(self, steps: int, sides: tuple[str, ...], period_s: float) -> None:
        self._sides, self._dt = sides, period_s
        self.trigger_frame = [-1] * steps
        self.trigger_error = np.zeros((steps, 2))
        self.left = np.zeros(steps)
        self.shift = np.zeros((steps, 2))
        self.landed_at = np.zeros(steps)

    def events(self) -> tuple[StepEvent, ...]:
        """The steps adjusted so far, in order."""
        events = []
        for j, frame in enumerate(self.trigger_frame):
            if frame < 0:
                continue
            left = float(self.left[j])
            events.append(StepEvent(
                frame * self._dt, j, self._sides[j],
                (float(self.trigger_error[j, 0]), float(self.trigger_error[j, 1])),
                (float(self.shift[j, 0]), float(self.shift[j, 1])),
                float(self.landed_at[j]), left == 0.0, left,
            ))  # fmt: skip
        return tuple(events)
