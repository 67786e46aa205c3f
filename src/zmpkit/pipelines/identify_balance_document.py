"""The report of ``zmpkit identify balance``: the error model, its residuals, the transients.

An identification has no bar of its own: the report states the error model and its largest
residual, the transients, and which trials were left out and why.
"""

from __future__ import annotations

import numpy as np

from zmpkit.analysis.provenance import capture_described
from zmpkit.analysis.report_document import Check, Figure, ReportDocument, Section, Text
from zmpkit.pipelines.balance_sections import identification_blocks
from zmpkit.pipelines.identify_balance import IdentifyBalanceResult

__all__ = ["identification_document"]


def identification_document(result: IdentifyBalanceResult) -> ReportDocument:
    """The report of an identification: the error model, its residuals, the transients."""
    source = result.source
    ident = result.identification.planes[result.plane]
    fit = ident.error_fit
    residual_mm = 1e3 * float(np.max(np.abs(fit.residuals), initial=0.0))
    p = ident.params
    checks = (
        Check(
            "steady-state error model (no bar)",
            "info",
            f"{fit.kind}, largest fit residual {residual_mm:.2f} mm over {len(fit.x_cmd)} trials",
        ),
        Check(
            "transient (no bar)",
            "info" if p.zeta is not None else "undefined",
            f"ζ = {p.zeta:.3f}, ω_n = {p.omega_n:.2f} rad/s"
            if p.zeta is not None and p.omega_n is not None
            else "no trial's transient could be fitted",
        ),
        Check(
            "every trial used",
            "met" if not ident.excluded else "missed",
            "; ".join(ident.excluded) or f"all {len(ident.trials)} trials settled",
        ),
    )
    figure = Figure(
        result.files["figure"],
        f"The settled force–torque ZMP [m] of each step against the commanded ZMP [m], with "
        f"the fitted error model and its 95 % band ({result.plane}; paper A Fig. 16).",
    )
    return ReportDocument(
        title=f"zmpkit identify balance: the DLIPM's error model from {source.name}",
        summary=(
            f"Steady-state error model (paper A eq. 13) and transients of the {result.plane} "
            f"steps recorded in `{source}`, chosen by leave-one-out cross-validation."
        ),
        checks=checks,
        sections=(
            Section(
                "Identification",
                (*identification_blocks(ident, result.plane, result.lean_length_m), figure),
            ),
            Section("Data", (Text("`params.yaml`: the identified DLIPM parameters."),)),
        ),
        provenance=capture_described(
            robot="recorded data",
            started_s=result.started_s,
            extra=(("data", str(source)),),
        ),
    )
