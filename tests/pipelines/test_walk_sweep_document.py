"""The sweep's report counts falls per controller and kind of case, from robustness.csv rows."""

from __future__ import annotations

from zmpkit.experiments.robustness import ROBUSTNESS_COLUMNS
from zmpkit.pipelines.walk_sweep import SweepConfig, SweepResult
from zmpkit.pipelines.walk_sweep_document import case_kind, walk_sweep_document


def _row(controller: str, fell: bool, **case: str) -> tuple[str, ...]:
    cells = {
        "controller": controller, "speed_mps": "0.2", "lateral_mps": "0", "turn_rad_s": "0",
        "step_duration_s": "0.5", "push_n": "0", "push_dir": "", "push_phase": "", "fault": "",
        "fell": "true" if fell else "false", "fall_time_s": "6.1" if fell else "",
        "fall_kind": "roll" if fell else "", "speed_error_pct": "" if fell else "1.0",
        "trunk_pitch_peak_hz": "" if fell else "2.0",
        "trunk_pitch_peak_amplitude_rad": "" if fell else "0.03", "adjusted_steps": "0",
        "uncaptured_steps": "0",
    }  # fmt: skip
    cells.update(case)
    return tuple(cells[c] for c in ROBUSTNESS_COLUMNS)


def test_falls_are_counted_per_controller_and_kind() -> None:
    rows = (
        _row("zmpip", False),
        _row("zmpip", True, push_n="20", push_dir="y", push_phase="0.25"),
        _row("zmpip", False, step_duration_s="0.35"),
        _row("open", True, fault="nan"),
    )
    result = SweepResult(SweepConfig(controllers=("zmpip", "open")), rows)
    doc = walk_sweep_document(result)
    zmpip, open_loop = doc.checks
    assert zmpip.status == "missed"
    assert zmpip.detail.startswith("1 of 3 walks fell: push 20 N y @ 0.25 (roll)")
    assert open_loop.status == "info"  # no bar for the open-loop playback
    breakdown = next(b for b in doc.blocks() if getattr(b, "caption", "").startswith("Falls by"))
    by_kind = {row[0]: row[1:] for row in breakdown.rows}  # type: ignore[union-attr]
    assert by_kind["push 20 N"] == ("1 / 1", "0 / 0")
    assert by_kind["sensor fault"] == ("0 / 0", "1 / 1")
    assert by_kind["step duration"] == ("0 / 1", "0 / 0")
    assert doc.status == "missed"


def test_case_kinds() -> None:
    row = dict(zip(ROBUSTNESS_COLUMNS, _row("dcm", False, turn_rad_s="0.3"), strict=True))
    assert case_kind(row) == "turning"
    row = dict(zip(ROBUSTNESS_COLUMNS, _row("dcm", False, speed_mps="0.05"), strict=True))
    assert case_kind(row) == "forward speed"
