"""What a walk's step adjustment did: the steps it moved, and those it could not make capture.

A :class:`StepEvent` is kept for every step the adjustment moved
(:mod:`zmpkit.walking.step_adjustment`); the walk's record, summary and report carry them, so
that a push no admissible step could catch is said, not hidden (:data:`NOT_CAPTURED`).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["NOT_CAPTURED", "StepEvent"]

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
