"""The ``zmpkit walk`` pipeline: pattern → whole-body IK → the virtual robot walks → report.

Paper B §III: a 3D-LIPM walk (preview control) played open-loop on the virtual NAO, whose
servos track the IK's joint angles with the chosen effects on. The pipeline reads only what
a user of the real robot reads — encoders, IMU, foot F-T sensors, joint torques (NAO: from
its motor currents) — plus the feet and torso positions of a motion capture; it never reads
the truth file (the simulator does).

Writes into the output folder :data:`SUMMARY_FILE` (:class:`WalkSummary` as JSON),
:data:`SERIES_FILE` (one row per 10 ms frame) and the figures of
:mod:`zmpkit.analysis.walk_plots`. Metrics are taken over the steady walk: from the end of
the second step to one step before the last one ends (or the fall).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

from zmpkit import _validate
from zmpkit.errors import ParameterError
from zmpkit.pipelines.walk_report import write_figures, write_series
from zmpkit.pipelines.walk_sim import ProgressCallback, WalkRecord, simulate_walk
from zmpkit.pipelines.walk_summary import WalkSummary, summarise_walk
from zmpkit.robots.nao import make_nao, nao_ik_model
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking import GaitParameters, PatternConfig, WalkCommand, generate_pattern
from zmpkit.walking.ik import JointTrajectory, solve_walking_ik
from zmpkit.walking.pattern import WalkingPattern

__all__ = [
    "NAO_WALK_COM_HEIGHT_M",
    "ROBOTS",
    "SERIES_FILE",
    "SUMMARY_FILE",
    "WalkConfig",
    "WalkResult",
    "WalkSummary",
    "run_walk",
]

ROBOTS: tuple[str, ...] = ("nao",)
"""Robots that can walk."""
SUMMARY_FILE = "summary.json"
SERIES_FILE = "timeseries.csv"
NAO_WALK_COM_HEIGHT_M = 0.25
"""CoM height of the walk [m]. NAO's crouch CoM is 0.26 m (nao-parameters.md §1), but 0.1 m
steps at 0.26 m stretch the trailing leg to its full length; 0.25 m keeps the knee bent."""


@dataclass(frozen=True)
class WalkConfig:
    """One walk, as ``zmpkit walk`` takes it.

    Attributes:
        robot: robot name, one of :data:`ROBOTS`.
        speed_mps: commanded forward speed [m/s].
        step_duration_s: one step [s].
        duration_s: walking time [s] (plus standing before and after).
        effects: ``"all"``, ``"none"`` or letters such as ``"M,I,G,F"``.
        seed: seed of the sensor noise.
        com_height_m: CoM height of the pattern [m].
        truth: a truth file for the simulator, or None for the shipped one.
        figures: whether to draw the figures.
    """

    robot: str = "nao"
    speed_mps: float = 0.2
    step_duration_s: float = 0.5
    duration_s: float = 10.0
    effects: str = "all"
    seed: int = 0
    com_height_m: float = NAO_WALK_COM_HEIGHT_M
    truth: str | None = None
    figures: bool = True

    def __post_init__(self) -> None:
        if self.robot not in ROBOTS:
            raise ParameterError(f"robot must be one of {', '.join(ROBOTS)}; got {self.robot!r}")
        _validate.finite("WalkConfig.speed_mps", self.speed_mps)
        _validate.positive("WalkConfig.step_duration_s", self.step_duration_s, "s")
        _validate.positive("WalkConfig.duration_s", self.duration_s, "s")
        _validate.positive("WalkConfig.com_height_m", self.com_height_m, "m")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"WalkConfig.seed must be an integer >= 0; got {self.seed!r}")
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)

    def pattern_config(self) -> PatternConfig:
        """The walking pattern this walk plays."""
        return PatternConfig(
            command=WalkCommand(v_x=self.speed_mps),
            duration_s=self.duration_s,
            gait=GaitParameters(step_duration_s=self.step_duration_s),
            com_height_m=self.com_height_m,
        )


@dataclass(frozen=True)
class WalkResult:
    """What a walk produced.

    Attributes:
        config: what was asked.
        summary: the metrics written to ``summary.json``.
        pattern: the planned walk.
        trajectory: the IK's joint angles and errors.
        record: the simulated signals.
        files: every file written, by role.
    """

    config: WalkConfig
    summary: WalkSummary
    pattern: WalkingPattern
    trajectory: JointTrajectory
    record: WalkRecord
    files: dict[str, Path] = field(default_factory=dict)


def run_walk(
    config: WalkConfig, out_dir: str | Path, progress: ProgressCallback | None = None
) -> WalkResult:
    """Plan, solve the IK, simulate and analyse one walk; write the results to ``out_dir``.

    Args:
        config: the walk.
        out_dir: output folder (created if missing).
        progress: called with (simulated time, total time) [s] during the simulation.

    Returns:
        The summary, signals and the files written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    pattern = generate_pattern(config.pattern_config())
    trajectory = solve_walking_ik(pattern, nao_ik_model())
    sim = make_nao(config.effects, config.truth, seed=config.seed)
    record = simulate_walk(sim, trajectory, progress)
    summary = summarise_walk(pattern, trajectory, record, config.effects, config.seed)
    files = {"summary": out / SUMMARY_FILE, "series": out / SERIES_FILE}
    files["summary"].write_text(json.dumps(asdict(summary), indent=2) + "\n", encoding="utf-8")
    write_series(files["series"], pattern, record)
    if config.figures:
        files.update(write_figures(out, config, pattern, record))
    return WalkResult(config, summary, pattern, trajectory, record, files)
