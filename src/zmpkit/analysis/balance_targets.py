"""The balance issue's acceptance figures, computed from Table 1 rows (never asserted here).

- error ratio at the farthest target: |DLIPM error| / |LIPM error| (target ≤ 0.20; paper A:
  2.0 / 11.6 = 0.17);
- mean |error| over targets ≠ 0: DLIPM / LIPM (target ≤ 1/3);
- targets ≥ 0.03 m where the DLIPM's overshoot, resp. settling time, is lower than LIPM's.

A ratio of errors means something only where the LIPM's error is measured: the far ratio is
undefined when the LIPM's settled error at the far target lies within :data:`RESOLVED_SE`
standard errors of its settled value, the mean ratio when fewer than half of the targets'
LIPM errors are resolved so (targets of a few millimetres on a noisy F-T ZMP, where a ratio
of two noise draws once read as a missed bar).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from zmpkit.analysis.table1 import Table1Row

__all__ = ["BalanceTargets", "balance_targets"]

FAR_TARGET_RATIO_MAX = 0.20
MEAN_ERROR_RATIO_MAX = 1.0 / 3.0
TRANSIENT_FROM_M = 0.03
RESOLVED_SE = 2.0
"""A LIPM error is measured when it exceeds this many standard errors of its settled value."""


@dataclass(frozen=True)
class BalanceTargets:
    """Acceptance figures of one plane (None where the data leave them undefined)."""

    plane: str
    far_target_m: float
    far_error_ratio: float | None
    mean_abs_error_lipm_pct: float | None
    mean_abs_error_dlipm_pct: float | None
    mean_error_ratio: float | None
    overshoot_lower: tuple[int, int]
    settling_lower: tuple[int, int]
    far_unresolved: str = ""
    mean_unresolved: str = ""

    def lines(self) -> list[str]:
        """Human-readable lines with each figure against its target."""
        return [
            f"error at {self.far_target_m:g} m, DLIPM/LIPM: {_num(self.far_error_ratio)} "
            f"(target ≤ {FAR_TARGET_RATIO_MAX:.2f})",
            f"mean |error| over targets ≠ 0: LIPM {_num(self.mean_abs_error_lipm_pct)} %, "
            f"DLIPM {_num(self.mean_abs_error_dlipm_pct)} %, ratio {_num(self.mean_error_ratio)}"
            f" (target ≤ {MEAN_ERROR_RATIO_MAX:.2f})",
            f"targets ≥ {TRANSIENT_FROM_M} m with lower overshoot under DLIPM: "
            f"{self.overshoot_lower[0]} of {self.overshoot_lower[1]}",
            f"targets ≥ {TRANSIENT_FROM_M} m with shorter settling under DLIPM: "
            f"{self.settling_lower[0]} of {self.settling_lower[1]}",
        ]


def _num(x: float | None) -> str:
    return "undefined" if x is None else f"{x:.3g}"


def balance_targets(plane: str, rows: Sequence[Table1Row]) -> BalanceTargets:
    """Compute the acceptance figures of ``rows`` (one plane's Table 1)."""
    far = max(rows, key=lambda r: abs(r.zmp_ref))
    lipm_far, dlipm_far = far.lipm.error_pct, far.dlipm.error_pct
    ratio = abs(dlipm_far / lipm_far) if lipm_far and dlipm_far is not None else None
    far_unresolved = _unresolved(far)
    if far_unresolved:
        ratio = None
    nonzero = [r for r in rows if r.zmp_ref != 0.0]
    lipm_mean = _mean_abs([r.lipm.error_pct for r in nonzero])
    dlipm_mean = _mean_abs([r.dlipm.error_pct for r in nonzero])
    mean_ratio = dlipm_mean / lipm_mean if lipm_mean and dlipm_mean is not None else None
    unresolved = [r for r in nonzero if _unresolved(r)]
    mean_unresolved = ""
    if nonzero and 2 * len(unresolved) > len(nonzero):
        mean_ratio = None
        mean_unresolved = (
            f"the LIPM's error is within {RESOLVED_SE:g} standard errors of its settled value "
            f"at {len(unresolved)} of {len(nonzero)} targets ≠ 0: too little error to measure "
            "a ratio; choose larger targets (--targets)"
        )
    transient = [r for r in rows if abs(r.zmp_ref) >= TRANSIENT_FROM_M - 1e-9]
    return BalanceTargets(
        plane=plane,
        far_target_m=far.zmp_ref,
        far_error_ratio=ratio,
        mean_abs_error_lipm_pct=lipm_mean,
        mean_abs_error_dlipm_pct=dlipm_mean,
        mean_error_ratio=mean_ratio,
        overshoot_lower=_count_lower(transient, "overshoot_pct"),
        settling_lower=_count_lower(transient, "settling_time_s"),
        far_unresolved=far_unresolved,
        mean_unresolved=mean_unresolved,
    )


def _unresolved(row: Table1Row) -> str:
    """Why the LIPM's settled error at ``row`` is not measured; empty when it is."""
    steady = row.lipm.steady
    if row.zmp_ref == 0.0 or steady.value is None or steady.std_error is None:
        return ""
    error_m = steady.value - row.zmp_ref
    if abs(error_m) > RESOLVED_SE * steady.std_error:
        return ""
    return (
        f"the LIPM's error at {row.zmp_ref:g} m, {1e3 * error_m:.3g} mm, is within "
        f"{RESOLVED_SE:g} standard errors ({1e3 * RESOLVED_SE * steady.std_error:.3g} mm) of "
        "its settled value: too little error to measure a ratio; choose larger targets "
        "(--targets)"
    )


def _mean_abs(values: list[float | None]) -> float | None:
    present = [v for v in values if v is not None]
    if not values or len(present) < len(values):
        return None
    return float(np.mean(np.abs(present)))


def _count_lower(rows: Sequence[Table1Row], attribute: str) -> tuple[int, int]:
    """Count the targets where DLIPM's ``attribute`` is lower than LIPM's.

    Returns:
        (targets where DLIPM < LIPM, targets compared); an undefined DLIPM value counts as
        not lower.
    """
    lower = 0
    for r in rows:
        lipm, dlipm = getattr(r.lipm, attribute), getattr(r.dlipm, attribute)
        if lipm is not None and dlipm is not None and dlipm < lipm:
            lower += 1
    return lower, len(rows)
