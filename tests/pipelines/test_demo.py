"""``zmpkit demo``: writes its report, figures and data; the numbers match closed forms."""

from __future__ import annotations

import csv
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from helpers.browser import check_page, chromium, screenshot
from helpers.golden_demo import (
    GOLDEN_DIR,
    REFERENCE_CPU_ENV,
    UPDATE_ENV,
    compare_with_golden,
    reference_cpu_missing,
    write_golden,
)
from zmpkit.pipelines.demo import DemoConfig, run_demo
from zmpkit.pipelines.demo_files import write_demo


def test_demo_writes_report_and_matches_second_order_theory(tmp_path: Path) -> None:
    config = DemoConfig(duration_s=30.0, balance=False, walking=False, compensation=False)
    result = write_demo(run_demo(config, tmp_path, echo=lambda _: None), tmp_path, lambda _: None)
    assert result.report_path is not None
    html = result.report_path.read_text()
    assert result.report_path.name == "report.html"
    assert "<h1>zmpkit demo: the LIPM and the robot that really moves</h1>" in html
    assert "to come" not in html  # the simulator fit is there, with its command
    assert "zmpkit identify sim --self-test" in html
    assert "Where the time went" in html  # each part's wall time, measured
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


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The whole demo, once, as a user runs it: its folder and what it printed.

    It runs in its own process on the golden set's instruction set
    (:data:`helpers.golden_demo.REFERENCE_CPU_ENV`), which must be fixed before NumPy loads.
    """
    out = tmp_path_factory.mktemp("demo") / "d"
    env = {**os.environ, **REFERENCE_CPU_ENV}
    main_of_zmpkit = (
        "import sys; from zmpkit.cli import main; sys.argv[0] = 'zmpkit'; sys.exit(main())"
    )
    command = [sys.executable, "-c", main_of_zmpkit, "demo", "--out", str(out)]
    run = subprocess.run(command, env=env, capture_output=True, text=True, check=False)
    assert run.returncode == 0, run.stderr[-4000:]
    return out, run.stdout


@pytest.mark.slow
def test_demo_command(demo_run: tuple[Path, str]) -> None:
    """The whole demo, including the quick balance pipeline on the virtual TEO."""
    out, printed = demo_run
    assert f"report: {out / 'report.html'}" in printed.splitlines()[-1]
    timing = next(line for line in printed.splitlines() if line.startswith("time by part: "))
    assert all(f"{part} " in timing for part in ("balance", "walks", "compensation"))
    assert 'href="balance/report.html"' in (out / "report.html").read_text()
    assert (out / "balance" / "table1.csv").exists()
    assert (out / "walk_all" / "summary.json").exists()
    assert (out / "compensate" / "summary.json").exists()
    videos = ("walk_side_by_side.mp4", "balance/step_trial.mp4")  # --video is the default
    assert all((out / v).stat().st_size > 10_000 for v in videos)
    html = (out / "report.html").read_text()
    assert all(f'src="{v}"' in html for v in videos)  # embedded as <video> elements


@pytest.mark.slow
def test_demo_outputs_equal_the_golden_set(demo_run: tuple[Path, str]) -> None:
    """Every number the demo writes is unchanged: summaries, Table 1, compensation JSON.

    The golden set (``tests/pipelines/golden/demo/``, :mod:`helpers.golden_demo`) holds the
    model's metrics and parameters, Table 1, the identified parameters, each balance sweep's
    meta.json, both walks' and the compensation's summaries and details, and a fingerprint
    (per column: count and sum) of every time series; numbers to 1e-9 relative, text exactly.
    With ``ZMPKIT_UPDATE_GOLDEN=1`` the run rewrites the set instead (an intended change).
    """
    out, _ = demo_run
    if (why := reference_cpu_missing()) is not None:
        pytest.skip(why)
    if os.environ.get(UPDATE_ENV) == "1":
        write_golden(out)
        return
    differences = compare_with_golden(out)
    assert not differences, f"demo outputs differ from {GOLDEN_DIR}:\n" + "\n".join(
        differences[:40]
    )


@pytest.mark.slow
def test_demo_report_loads_in_a_real_browser(demo_run: tuple[Path, str]) -> None:
    """Headless Chromium opens report.html: every image and video loads, the verdict is there."""
    browser = chromium()
    if browser is None:
        if os.environ.get("CI"):
            pytest.fail("CI must have Chromium: .ci/run installs the Debian package 'chromium'")
        pytest.skip("no Chromium here (apt-get install chromium); CI runs this test")
    out, _ = demo_run
    seen = check_page(out / "report.html", browser)
    assert seen.verdict
    assert seen.broken == []
    assert len(seen.images) >= 8  # the model, Table 1 plane figures, walks, compensation
    assert len(seen.videos) == 2  # the walks side by side, the balance step trial
    assert all(v["width"] > 0 for v in seen.videos)
    shot = screenshot(out / "report.html", browser, out / "report_first_screen.png")
    assert shot.stat().st_size > 10_000  # a rendered page, not an empty frame
