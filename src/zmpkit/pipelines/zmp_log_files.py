"""The files of ``zmpkit zmp``: ``zmp.csv``, ``zmp.png`` and the report."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from zmpkit.analysis.report_files import write_report
from zmpkit.analysis.zmp_plot import plot_zmp_series
from zmpkit.io import write_zmp_csv
from zmpkit.pipelines.zmp_document import zmp_document
from zmpkit.pipelines.zmp_log import ZmpRunResult

__all__ = ["write_zmp_log"]


def write_zmp_log(
    result: ZmpRunResult, out_dir: str | Path, report_format: str = "html"
) -> ZmpRunResult:
    """Write ``zmp.csv``, ``zmp.png`` and the report into ``out_dir`` (created if missing).

    A figure that cannot be drawn is a :class:`~zmpkit.errors.FigureWarning` and a
    placeholder image, not an error.

    Returns:
        ``result`` with the files written, by role (``csv``, ``figure``, ``report``).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    series = result.series
    files = {
        "csv": write_zmp_csv(series, out / "zmp.csv"),
        "figure": plot_zmp_series(
            series, out / "zmp.png", title=f"Measured ZMP: {result.log_source}"
        ),
    }
    written = replace(result, files=files)
    files["report"] = write_report(zmp_document(written), out, report_format)
    return replace(result, files=files)
