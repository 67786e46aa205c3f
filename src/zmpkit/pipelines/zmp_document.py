"""The report of ``zmpkit zmp``: a recorded force–torque log's ZMP, where it is defined.

A log has no bar to meet; the report states what was read and what came out: how many
samples, on how many the ZMP is defined (a foot above the contact threshold), the phases of
contact, and the ZMP's range, so a wrong mount or unit shows at a glance.
"""

from __future__ import annotations

import numpy as np

from zmpkit.analysis.provenance import capture_described, file_sha256
from zmpkit.analysis.report_document import Check, Figure, ReportDocument, Section, Table, Text
from zmpkit.pipelines.zmp_log import ZmpRunResult

__all__ = ["zmp_document"]


def zmp_document(result: ZmpRunResult) -> ReportDocument:
    """The ZMP log's report."""
    log_path, feet_source = result.log_path, result.feet_source
    contact_threshold_n = result.contact_threshold_n
    s = result.series
    n = len(s.time)
    defined = int(np.count_nonzero(s.defined))
    rows = _log_rows(result)
    checks = (
        Check(
            "ZMP defined (no bar)",
            "info" if defined else "undefined",
            f"on {defined} of {n} samples ({_pct(defined, n)})"
            if defined
            else f"no sample has a foot above the contact threshold {contact_threshold_n:g} N",
        ),
    )
    return ReportDocument(
        title=f"zmpkit zmp: the measured ZMP of {log_path.name}",
        summary=(
            f"The ZMP of the recorded force–torque log `{log_path}`, computed from both feet's "
            f"wrenches with the sensor mounts of {feet_source}; a foot counts as in contact "
            f"above {contact_threshold_n:g} N of vertical force, and where no foot does, the "
            "ZMP is undefined (an empty cell in `zmp.csv`, a gap in the figure)."
        ),
        checks=checks,
        sections=(
            Section(
                "The log",
                (
                    Table(("quantity", "value"), tuple(rows), "What the log holds."),
                    Figure(
                        result.files["figure"],
                        "Measured ZMP in the world frame [m], x and y, over time [s] (gaps: "
                        "undefined), and the vertical force of each foot [N] with the contact "
                        "threshold.",
                    ),
                ),
            ),
            Section("Data", (Text("`zmp.csv`: time [s], ZMP x and y [m], contact flags."),)),
        ),
        provenance=capture_described(
            robot=feet_source,
            started_s=result.started_s,
            extra=(("log", str(log_path)), ("log SHA-256", file_sha256(log_path) or "–")),
        ),
    )


def _log_rows(result: ZmpRunResult) -> list[tuple[str, str]]:
    """Samples, duration [s], contact phases and, where defined, the ZMP's range [m]."""
    s = result.series
    n = len(s.time)
    defined = int(np.count_nonzero(s.defined))
    both = int(np.count_nonzero(s.contact_right & s.contact_left))
    right = int(np.count_nonzero(s.contact_right & ~s.contact_left))
    left = int(np.count_nonzero(s.contact_left & ~s.contact_right))
    duration = float(s.time[-1] - s.time[0]) if n > 1 else 0.0
    rows = [
        ("samples", f"{n}"),
        ("duration [s]", f"{duration:.3f}"),
        ("ZMP defined (a foot in contact)", f"{defined} ({_pct(defined, n)})"),
        ("double support", f"{both} ({_pct(both, n)})"),
        ("right foot only", f"{right} ({_pct(right, n)})"),
        ("left foot only", f"{left} ({_pct(left, n)})"),
        ("no foot in contact (ZMP undefined)", f"{n - defined} ({_pct(n - defined, n)})"),
    ]
    if defined:
        zmp = s.zmp[s.defined]
        rows += [
            ("ZMP x range in world [m]", f"{zmp[:, 0].min():.4f} … {zmp[:, 0].max():.4f}"),
            ("ZMP y range in world [m]", f"{zmp[:, 1].min():.4f} … {zmp[:, 1].max():.4f}"),
        ]
    return rows


def _pct(part: int, whole: int) -> str:
    return f"{100.0 * part / whole:.1f} %" if whole else "–"
