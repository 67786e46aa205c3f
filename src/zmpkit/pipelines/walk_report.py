"""Draw paper B's figures of one walk (trunk pitch, its spectrum, feet, joint tracking)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zmpkit.analysis import walk_plots as plots
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_trial import WalkRecord
from zmpkit.robots.registry import get_robot
from zmpkit.signals.contact_phases import double_support_distance
from zmpkit.signals.spectra import amplitude_spectrum
from zmpkit.walking.pattern import WalkingPattern

__all__ = ["series_joints", "write_figures"]


def series_joints(config: WalkConfig) -> tuple[str, ...]:
    """The walking robot's hip, knee and ankle pitch joints, left leg then right leg."""
    return get_robot(config.robot, needs="walking").require_walking().series_joints


def write_figures(
    out: Path,
    config: WalkConfig,
    pattern: WalkingPattern,
    record: WalkRecord,
    window_s: tuple[float, float] | None = None,
) -> dict[str, Path]:
    """Draw paper B's figures of one walk into ``out``; return them by role.

    The spectrum is taken over ``window_s`` [s] (the summary's steady window, so the figure
    shows the numbers of ``summary.json``), or over the whole record when None.
    """
    label = (
        f"{config.robot.upper()} {config.speed_mps:g} m/s, effects {config.effects}, "
        f"{config.controller}"
    )
    t = record.time_s
    files = {"trunk_pitch": plots.plot_trunk_pitch(t, record.trunk_pitch_rad,
                                                   out / "trunk_pitch.png", label)}  # fmt: skip
    keep = np.ones(t.size, dtype=bool)
    if window_s is not None:
        keep = (t >= window_s[0]) & (t <= window_s[1])
    if np.count_nonzero(keep) >= 8:
        spectrum = amplitude_spectrum(record.trunk_pitch_rad[keep], float(np.median(np.diff(t))))
        step_hz = 1.0 / config.step_duration_s
        files["spectrum"] = plots.plot_trunk_spectrum(
            spectrum, step_hz, out / "trunk_pitch_spectrum.png", label
        )
    contact = record.in_contact()
    sole_x = record.sole_in_world[..., 0]
    feet = dict(enumerate(record.feet))
    files["feet"] = plots.plot_feet_in_contact(
        t, {f: sole_x[:, i] for i, f in feet.items()}, {f: contact[:, i] for i, f in feet.items()},
        out / "feet_in_contact.png", label,
    )  # fmt: skip
    step_length = abs(config.speed_mps) * config.step_duration_s
    files["feet_distance"] = plots.plot_feet_distance(
        t, double_support_distance(sole_x, contact), step_length,
        out / "feet_distance.png", label,
    )  # fmt: skip
    right_leg = series_joints(config)[3:]
    for joint in right_leg[::-1]:
        j = record.joint(joint)
        files[joint] = plots.plot_joint_tracking(
            t, record.q_cmd_rad[:, j], record.q_meas_rad[:, j], record.torque_nm[:, j],
            out / f"joint_{joint}.png", f"{label}: {joint}",
        )  # fmt: skip
    return files
