"""The verdict of ``zmpkit balance``: paper A's bars per plane, transient counts, warnings.

Each bar is met, missed, or undefined and why; the far target says whether the error model
was fitted on it or held out, so no fitted target passes for a validated one.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from zmpkit.analysis.balance_targets import TRANSIENT_FROM_M, balance_targets
from zmpkit.analysis.balance_verdict import Bar, PlaneVerdict
from zmpkit.analysis.report_document import Check
from zmpkit.analysis.table1 import Table1Row
from zmpkit.pipelines.balance import BalanceResult

__all__ = ["balance_checks"]


def balance_checks(result: BalanceResult, verdicts: dict[str, PlaneVerdict]) -> tuple[Check, ...]:
    """Paper A's bars per plane, the transient counts, and the warnings."""
    fitted = set(np.round(result.config.fit_targets_m, 6))
    checks: list[Check] = []
    for name, verdict in verdicts.items():
        rows = result.planes[name].rows
        far = max(rows, key=lambda r: abs(r.zmp_ref))
        role = "fitted" if round(far.zmp_ref, 6) in fitted else "held out"
        for bar in verdict.bars:
            checks.append(_bar_check(name, bar, far.zmp_ref, role))
        targets = balance_targets(name, rows)
        for what, (lower, total) in (
            ("lower overshoot", targets.overshoot_lower),
            ("shorter 5 % settling", targets.settling_lower),
        ):
            checks.append(
                Check(
                    f"{name}: DLIPM {what} than LIPM (no bar)",
                    "info",
                    f"at {lower} of {total} targets ≥ {TRANSIENT_FROM_M:g} m",
                )
            )
        checks += _feedback_checks(name, rows)
        checks += [Check(f"{name}: warning", "info", w) for w in verdict.warnings]
    for name, why in result.failed_planes.items():
        checks.append(Check(f"{name}: paper A's bars", "undefined", f"the plane failed: {why}"))
    return tuple(checks)


def _feedback_checks(plane: str, rows: Sequence[Table1Row]) -> list[Check]:
    """DLIPM+feedback against the LIPM and the DLIPM (no bar of paper A): error ratios."""
    if not any(r.dlipm_fb is not None for r in rows):
        return []
    far = max(rows, key=lambda r: abs(r.zmp_ref))
    means = {}
    for name in ("lipm", "dlipm", "lipm_pid", "dlipm_fb"):
        errors = [r.outcomes()[name].error_pct for r in rows if r.zmp_ref != 0.0]
        means[name] = (
            None
            if not errors or any(e is None for e in errors)
            else float(np.mean([abs(e) for e in errors if e is not None]))
        )
    far_fb = far.outcomes()["dlipm_fb"].error_pct
    detail = (
        f"error at {far.zmp_ref:g} m {_pct_text(far_fb)}; mean |error| over targets ≠ 0: "
        f"DLIPM+feedback {_pct_text(means['dlipm_fb'])}, DLIPM {_pct_text(means['dlipm'])}, "
        f"LIPM+PID {_pct_text(means['lipm_pid'])}, LIPM {_pct_text(means['lipm'])}"
    )
    lipm, fb = means["lipm"], means["dlipm_fb"]
    if lipm and fb is not None:
        detail += f"; ratio DLIPM+feedback / LIPM {fb / lipm:.3f}"
    return [Check(f"{plane}: DLIPM+feedback (no bar of paper A)", "info", detail)]


def _pct_text(value: float | None) -> str:
    return "undefined (a trial did not settle)" if value is None else f"{value:.2f} %"


def _bar_check(plane: str, bar: Bar, far_m: float, role: str) -> Check:
    if bar.name == "far error ratio":
        name = f"{plane}: |DLIPM error| / |LIPM error| at {far_m:g} m (a {role} target)"
    else:
        name = f"{plane}: mean |DLIPM error| / mean |LIPM error|, targets ≠ 0"
    value = "undefined" if bar.value is None else f"{bar.value:.3f}"
    detail = f"{value} against the bar ≤ {bar.limit:.2f}"
    if bar.why:
        detail += f": {bar.why}"
    status = bar.state if bar.state in ("met", "missed", "undefined") else "undefined"
    return Check(name, status, detail)  # type: ignore[arg-type]
