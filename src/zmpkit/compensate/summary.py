"""What a compensation achieved on its validation walks: the ``summary.json`` of a run.

Per validation walk (walks tuning never saw), the trunk pitch's step-frequency amplitude
("peak") and standard deviation ("std") over the steady walk, without and with the
compensation, and their reductions :math:`100 (1 - after/before)` [%]. The means cover only
the walks where neither version fell: a fall is counted (``compensated_falls``), never turned
into a number.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import TypeAlias

import numpy as np

from zmpkit.compensate.methods import CompensatedWalk

__all__ = [
    "EXTRA_SUMMARY_KEYS",
    "OSCILLATION_KEYS",
    "SUMMARY_KEYS",
    "CompensationSummary",
    "TrunkOscillationChange",
    "ValidationWalkOutcome",
    "summary_of",
]

EXTRA_SUMMARY_KEYS: tuple[str, ...] = (
    "walks_compared", "compensated_falls", "walks_made_to_fall", "rejected",
)  # fmt: skip
"""Keys zmpkit adds: how many validation walks the means cover (neither version fell), how
many compensated walks fell, how many of those stood without the compensation, and whether
the compensation is rejected for it (any such walk rejects it)."""


def _reduction(before: float | None, after: float | None) -> float | None:
    """100·(1 − after/before) [%]; None when either walk has no oscillation to compare."""
    if before is None or after is None or before == 0.0:
        return None
    return float(100.0 * (1.0 - after / before))


def _peak(walk: CompensatedWalk) -> float | None:
    """Step-frequency peak [rad]; None for a walk that fell (it has no steady oscillation)."""
    return None if walk.fell else walk.step_peak_rad


def _std(walk: CompensatedWalk) -> float | None:
    """Trunk-pitch std [rad]; None for a walk that fell."""
    return None if walk.fell else walk.std_rad


def _mean(values: list[float | None]) -> float | None:
    """Mean of the values that are not None; None if there are none."""
    kept = [v for v in values if v is not None]
    return float(np.mean(kept)) if kept else None


Oscillation: TypeAlias = tuple[
    float | None, float | None, float | None, float | None, float | None, float | None
]
"""The fields of a :class:`TrunkOscillationChange`, in order."""


def _oscillation(
    peaks: tuple[float | None, float | None], stds: tuple[float | None, float | None]
) -> Oscillation:
    """The change from (before, after) peak amplitudes and stds [rad], reductions added."""
    return peaks[0], peaks[1], _reduction(*peaks), stds[0], stds[1], _reduction(*stds)


@dataclass(frozen=True)
class TrunkOscillationChange:
    """The trunk pitch's oscillation without and with the compensation, and its reductions.

    Of one validation walk (None where a version fell), or the means over the walks compared.

    Attributes:
        baseline_peak_amplitude_rad: uncompensated step-frequency amplitude [rad].
        compensated_peak_amplitude_rad: compensated step-frequency amplitude [rad].
        peak_reduction_pct: the amplitude's reduction [%].
        baseline_std_rad: uncompensated trunk-pitch std [rad].
        compensated_std_rad: compensated trunk-pitch std [rad].
        std_reduction_pct: the std's reduction [%].
    """

    baseline_peak_amplitude_rad: float | None
    compensated_peak_amplitude_rad: float | None
    peak_reduction_pct: float | None
    baseline_std_rad: float | None
    compensated_std_rad: float | None
    std_reduction_pct: float | None


OSCILLATION_KEYS: tuple[str, ...] = tuple(f.name for f in fields(TrunkOscillationChange))
"""The fields of :class:`TrunkOscillationChange`, in order."""
SUMMARY_KEYS: tuple[str, ...] = ("method", *OSCILLATION_KEYS, "validation_walks")
"""Keys of ``summary.json`` (``alg1`` adds ``iteration_rms_m``)."""
_WALK_KEYS: tuple[str, ...] = (
    "speed_mps", "seed", "duration_s", *OSCILLATION_KEYS, "baseline_fell", "compensated_fell",
    "step_duration_s", "controller", "robot_change",
)  # fmt: skip
"""Keys of a walk's entry of ``summary.json``, in order."""


@dataclass(frozen=True)
class ValidationWalkOutcome(TrunkOscillationChange):
    """One validation walk without and with the compensation (None where a version fell).

    Its trunk oscillation's change is that of :class:`TrunkOscillationChange`.

    Attributes:
        speed_mps: commanded speed [m/s].
        seed: sensor-noise seed [-].
        duration_s: walking time [s].
        baseline_fell: whether the uncompensated walk fell.
        compensated_fell: whether the compensated walk fell.
        step_duration_s: step duration [s].
        controller: the walking controller.
        robot_change: what its robot changes from the shipped one ("" for none).
    """

    speed_mps: float
    seed: int
    duration_s: float
    baseline_fell: bool
    compensated_fell: bool
    step_duration_s: float = 0.5
    controller: str = "open"
    robot_change: str = ""

    @classmethod
    def of(cls, base: CompensatedWalk, comp: CompensatedWalk) -> ValidationWalkOutcome:
        """The outcome of one walk from its two versions."""
        w = base.walk
        return cls(
            *_oscillation((_peak(base), _peak(comp)), (_std(base), _std(comp))),
            w.commanded_speed_mps, w.seed, w.duration_s, base.fell, comp.fell,
            w.step_duration_s, w.controller, w.truth_label,
        )  # fmt: skip

    def as_dict(self) -> dict[str, object]:
        """The walk's entry of ``summary.json``."""
        return {k: getattr(self, k) for k in _WALK_KEYS}


@dataclass(frozen=True)
class CompensationSummary(TrunkOscillationChange):
    """The means over the validation walks where neither version fell (module docstring).

    The oscillation's change (:class:`TrunkOscillationChange`) is that of the means: the mean
    amplitudes and stds [rad], and the reductions of the means [%].

    Attributes:
        method: the compensation method.
        validation_walks: every validation walk, fallen ones included.
        walks_compared: walks the means cover (neither version fell) [-].
        compensated_falls: compensated walks that fell [-].
        walks_made_to_fall: compensated walks that fell where the uncompensated one stood [-].
        rejected: whether any validation walk was made to fall (the compensation is then not
            to be used).
        iteration_rms_m: Algorithm 1's RMS ZMP error per iteration [m]; None for others.
    """

    method: str
    validation_walks: tuple[ValidationWalkOutcome, ...]
    walks_compared: int
    compensated_falls: int
    iteration_rms_m: tuple[float, ...] | None = None
    walks_made_to_fall: int = 0
    rejected: bool = False

    def as_dict(self) -> dict[str, object]:
        """Return the contents of ``summary.json``.

        These are :data:`SUMMARY_KEYS`, the counts, and ``iteration_rms_m`` for Algorithm 1.
        """
        out: dict[str, object] = {k: getattr(self, k) for k in SUMMARY_KEYS}
        out["validation_walks"] = [w.as_dict() for w in self.validation_walks]
        out.update({k: getattr(self, k) for k in EXTRA_SUMMARY_KEYS})
        if self.iteration_rms_m is not None:
            out["iteration_rms_m"] = list(self.iteration_rms_m)
        return out


def summary_of(
    method: str, baseline: Sequence[CompensatedWalk], compensated: Sequence[CompensatedWalk]
) -> CompensationSummary:
    """The summary of a run from its validation walks, without and with compensation."""
    pairs = list(zip(baseline, compensated, strict=True))
    both = [(b, c) for b, c in pairs if not b.fell and not c.fell]
    peaks = [_mean([_peak(w[k]) for w in both]) for k in (0, 1)]
    stds = [_mean([_std(w[k]) for w in both]) for k in (0, 1)]
    rms = tuple(compensated[0].iteration_rms_m) if method == "alg1" else None
    made_to_fall = sum(c.fell and not b.fell for b, c in pairs)
    return CompensationSummary(
        *_oscillation((peaks[0], peaks[1]), (stds[0], stds[1])), method,
        tuple(ValidationWalkOutcome.of(b, c) for b, c in pairs), len(both),
        sum(c.fell for _, c in pairs), rms, made_to_fall, made_to_fall > 0,
    )  # fmt: skip
