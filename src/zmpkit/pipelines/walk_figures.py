"""Draw paper B's figures of one walk (trunk pitch and roll, spectrum, feet, joint tracking)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from zmpkit.analysis import walk_plots as plots
from zmpkit.analysis.labels import effects_name
from zmpkit.analysis.walk_compare_plot import WalkTrace, plot_walk_comparison
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_summary import (
    WalkSummary,
    measured_double_support_distance,
    planned_double_support_distance,
)
from zmpkit.experiments.walk_trial import FALL_TILT_RAD, WalkRecord
from zmpkit.signals.spectra import amplitude_spectrum
from zmpkit.walking.pattern import WalkingPattern

__all__ = [
    "COMPARISON_FILE",
    "JOINT_PLOT_STEPS",
    "joint_plot_span",
    "series_joints",
    "write_effects_comparison",
    "write_figures",
]

JOINT_PLOT_STEPS = 4
"""Steps shown by the joint-tracking figures: enough to see the step pattern, few enough
that errors of a few hundredths of a radian stay visible."""


def series_joints(config: WalkConfig) -> tuple[str, ...]:
    """The walking robot's hip, knee and ankle pitch joints, left leg then right leg."""
    return config.robot.require_walking().series_joints


def joint_plot_span(
    summary: WalkSummary, step_duration_s: float, end_s: float
) -> tuple[float, float]:
    """The time span [s] of the joint figures: :data:`JOINT_PLOT_STEPS` steps.

    They start at the steady window (after the start-up steps); a walk that fell shows the
    steps up to its fall instead, which is where the tracking went wrong.
    """
    span = JOINT_PLOT_STEPS * step_duration_s
    if summary.fall_time_s is not None:
        stop = min(summary.fall_time_s + 0.5 * step_duration_s, end_s)
        return max(0.0, stop - span), stop
    start = summary.window_s[0]
    return start, min(start + span, end_s)


@dataclass(frozen=True)
class _Marks:
    """What every time plot of one walk shares: its label, steady window, fall and pushes."""

    label: str
    window_s: tuple[float, float] | None
    fall: plots.FallMark | None
    pushes: tuple[plots.PushMark, ...]


def write_figures(
    out: Path,
    config: WalkConfig,
    pattern: WalkingPattern,
    record: WalkRecord,
    summary: WalkSummary,
) -> dict[str, Path]:
    """Draw paper B's figures of one walk into ``out``; return them by role.

    Angles are in [rad]. The spectrum is taken over the summary's steady window, so its
    peak is the one in ``summary.json``; time plots shade that window and mark a fall.
    """
    title = config.robot.title
    marks = _Marks(
        label=(
            f"{title} {config.speed_mps:g} m/s, {config.step_duration_s:g} s steps, "
            f"{effects_name(config.effects)}, {config.controller}"
        ),
        window_s=None if summary.fell else summary.window_s,  # a fall has no metrics' window
        fall=(
            plots.FallMark(summary.fall_time_s, summary.fall_kind or "tilt")
            if summary.fell and summary.fall_time_s is not None
            else None
        ),
        pushes=tuple(
            plots.PushMark(p.time_s, p.duration_s, f"push {p.force_n:g} N {_signed(p.direction)}")
            for p in config.pushes
        ),
    )
    files = _trunk_figures(out, config, record, summary, marks)
    files |= _feet_figures(out, pattern, record, marks)
    files |= _joint_figures(out, config, record, summary, marks)
    return files


def _trunk_figures(
    out: Path, config: WalkConfig, record: WalkRecord, summary: WalkSummary, marks: _Marks
) -> dict[str, Path]:
    """Trunk pitch and roll over time [rad], and the pitch's spectrum over the steady window."""
    t, label, window, fall, pushes = (
        record.time_s,
        marks.label,
        marks.window_s,
        marks.fall,
        marks.pushes,
    )
    files = {}
    files["trunk_pitch"] = plots.plot_trunk_tilt(
        t, record.trunk_pitch_rad, out / "trunk_pitch.png", label, axis="pitch",
        fall_tilt_rad=FALL_TILT_RAD, window_s=window, fall=fall, pushes=pushes,
    )  # fmt: skip
    files["trunk_roll"] = plots.plot_trunk_tilt(
        t, record.trunk_roll_rad, out / "trunk_roll.png", label, axis="roll",
        fall_tilt_rad=FALL_TILT_RAD, window_s=window, fall=fall, pushes=pushes,
    )  # fmt: skip
    keep = (t >= summary.window_s[0]) & (t <= summary.window_s[1])
    if window is not None and np.count_nonzero(keep) >= 8:  # a fall has no steady spectrum
        spectrum = amplitude_spectrum(record.trunk_pitch_rad[keep], float(np.median(np.diff(t))))
        files["spectrum"] = plots.plot_trunk_spectrum(
            spectrum, 1.0 / config.step_duration_s, out / "trunk_pitch_spectrum.png", label,
            window_s=window,
        )  # fmt: skip
    return files


def _feet_figures(
    out: Path, pattern: WalkingPattern, record: WalkRecord, marks: _Marks
) -> dict[str, Path]:
    """The soles along x [m] while in contact, and the feet's distance in double support [m]."""
    t, label, fall = record.time_s, marks.label, marks.fall
    contact = record.in_contact()
    sole_x = record.sole_in_world[..., 0]
    feet = dict(enumerate(record.feet))
    files = {}
    files["feet"] = plots.plot_feet_in_contact(
        t, {f: sole_x[:, i] for i, f in feet.items()}, {f: contact[:, i] for i, f in feet.items()},
        out / "feet_in_contact.png", label, fall=fall,
    )  # fmt: skip
    planned = np.interp(
        t, pattern.feet.time_s, planned_double_support_distance(pattern), left=np.nan,
        right=np.nan,
    )  # fmt: skip
    files["feet_distance"] = plots.plot_feet_distance(
        t, measured_double_support_distance(pattern, record), planned,
        out / "feet_distance.png", label, window_s=marks.window_s, fall=fall, pushes=marks.pushes,
    )  # fmt: skip
    return files


def _joint_figures(
    out: Path, config: WalkConfig, record: WalkRecord, summary: WalkSummary, marks: _Marks
) -> dict[str, Path]:
    """The right leg's joints over :data:`JOINT_PLOT_STEPS` steps: tracking [rad], torque [N·m]."""
    t, fall = record.time_s, marks.fall
    start, stop = joint_plot_span(summary, config.step_duration_s, float(t[-1]))
    span = (t >= start) & (t <= stop)
    right_leg = series_joints(config)[3:]
    files = {}
    for joint in right_leg[::-1]:
        j = record.joint(joint)
        files[joint] = plots.plot_joint_tracking(
            t[span], record.q_cmd_rad[span, j], record.q_meas_rad[span, j],
            record.torque_nm[span, j], out / f"joint_{joint}.png", f"{marks.label}: {joint}",
            fall=fall if fall is not None and start <= fall.time_s <= stop else None,
        )  # fmt: skip
    return files


def _signed(direction: str) -> str:
    """A push direction with its sign: ``+x``, ``-y``."""
    return direction if direction.startswith("-") else f"+{direction}"


COMPARISON_FILE = "walk_rigid_vs_all_effects.png"
"""The rigid walk against the all-effects walk, overlaid (paper B Fig. 6)."""


def write_effects_comparison(walks: Mapping[str, tuple[WalkConfig, WalkSummary, WalkRecord]],
                             path: Path) -> Path:  # fmt: skip
    """Overlay the trunk pitch and its spectrum of walks that differ in their effects.

    Args:
        walks: effect-set code (``none``, ``all``, ...) → the walk's config, summary, record.
            The walks share speed and step duration (the first one's are used).
        path: the PNG file to write.
    """
    first = next(iter(walks.values()))[0]
    traces = {
        effects_name(effects): WalkTrace(
            record.time_s,
            record.trunk_pitch_rad,
            summary.window_s,
            summary.fall_time_s if summary.fell else None,
        )
        for effects, (_, summary, record) in walks.items()
    }
    title = (
        f"{first.robot.title}, {first.speed_mps:g} m/s, {first.step_duration_s:g} s "
        f"steps, {first.controller}: trunk pitch by effect set (paper B Fig. 6)"
    )
    return plot_walk_comparison(traces, first.step_duration_s, path, title)
