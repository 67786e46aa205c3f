"""The files of ``zmpkit identify balance``: ``fig16_<plane>.png``, ``params.yaml``, the report."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from zmpkit.analysis.balance_plots import plot_error_fit
from zmpkit.analysis.report_files import write_report
from zmpkit.pipelines.identify_balance import IdentifyBalanceResult
from zmpkit.pipelines.identify_balance_document import identification_document

__all__ = ["write_identify_balance"]


def write_identify_balance(
    result: IdentifyBalanceResult, out_dir: str | Path, report_format: str = "html"
) -> IdentifyBalanceResult:
    """Write the error-model figure, ``params.yaml`` and the report into ``out_dir``.

    Args:
        result: the identification, from
            :func:`~zmpkit.pipelines.identify_balance.run_identify_balance`.
        out_dir: output folder, created if missing.
        report_format: ``html`` (``report.html``), ``md`` (``report.md``) or ``both``.

    Returns:
        ``result`` with the files written, by role (``figure``, ``params``, ``report``).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plane = result.plane
    identification = result.identification
    files = {
        "figure": plot_error_fit(
            identification.planes[plane], (), out / f"fig16_{plane}.png", plane=plane
        ),
        "params": identification.params.to_yaml(out / "params.yaml"),
    }
    written = replace(result, files=files)
    files["report"] = write_report(identification_document(written), out, report_format)
    return replace(result, files=files)
