"""``zmpkit demo``: writes its report, figures and data; the numbers match closed forms."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from zmpkit.cli import main
from zmpkit.pipelines.demo import DemoConfig, run_demo


def test_demo_writes_report_and_matches_second_order_theory(tmp_path: Path) -> None:
    result = run_demo(
        tmp_path,
        DemoConfig(duration_s=30.0, balance=False, walking=False, compensation=False),
        echo=lambda _: None,
    )
    assert result.report_path.read_text().startswith("# zmpkit demo")
    assert all(p.stat().st_size > 1000 for p in result.figures)
    zeta = 0.8
    overshoot = 100 * math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2))  # 1.5165 %
    for name in ("dlipm_si", "dlipm_paper_units"):
        assert result.metrics[name].overshoot_pct == pytest.approx(overshoot, rel=1e-3)
    # both designs hold the linearised LIPM angle x/l (the paper's in degrees)
    x, length = 0.09, 0.893
    assert result.metrics["dlipm_si"].final_value == pytest.approx(x / length, rel=1e-12)
    with (tmp_path / "step_metrics.csv").open() as f:
        rows = {r["model"]: r for r in csv.DictReader(f)}
    assert rows["lipm"]["stable"] == "False"
    assert float(rows["dlipm_paper_units"]["omega_n_rad_s"]) == pytest.approx(0.4379, abs=1e-4)
    assert float(rows["dlipm_si"]["omega_n_rad_s"]) == pytest.approx(math.sqrt(9.81 / length))


@pytest.mark.slow
def test_demo_command(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The whole demo, including the quick balance pipeline on the virtual TEO (~70 s)."""
    assert main(["demo", "--out", str(tmp_path / "d")]) == 0
    assert f"report: {tmp_path / 'd' / 'report.md'}" in capsys.readouterr().out
    assert "(balance/report.md)" in (tmp_path / "d" / "report.md").read_text()
    assert (tmp_path / "d" / "balance" / "table1.csv").exists()
    assert (tmp_path / "d" / "walk_all" / "summary.json").exists()
    assert (tmp_path / "d" / "compensate" / "summary.json").exists()
    videos = ("walk_side_by_side.mp4", "balance/step_trial.mp4")  # --video is the default
    assert all((tmp_path / "d" / v).stat().st_size > 10_000 for v in videos)
    assert (
        "Videos: [walk_side_by_side.mp4](walk_side_by_side.mp4), [balance/step_trial.mp4]"
        in (tmp_path / "d" / "report.md").read_text()
    )
