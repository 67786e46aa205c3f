"""``zmpkit balance`` as one call: the pipeline with progress bars, then its artefacts."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from zmpkit.pipelines.balance import BalanceConfig, run_balance
from zmpkit.pipelines.balance_report import BalanceArtifacts, write_balance_outputs
from zmpkit.pipelines.progress import SweepProgress

__all__ = ["balance_with_progress"]


def balance_with_progress(
    config: BalanceConfig, out_dir: str | Path, echo: Callable[[str], None] = print
) -> BalanceArtifacts:
    """Run the balance pipeline with a progress bar per sweep and write its artefacts."""
    with SweepProgress() as progress:
        result = run_balance(config, out_dir, progress=progress, echo=echo)
    return write_balance_outputs(result, out_dir)
