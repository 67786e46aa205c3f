"""The robustness matrix of a walking controller: speeds, steps, directions, pushes, faults.

One :class:`RobustnessCase` is one walk that differs from the nominal one (0.2 m/s forward,
0.5 s steps, 10 s) in one thing that matters for balance:

- forward speed 0.05–0.30 m/s (0.5 s steps);
- step duration 0.35–0.70 s (0.2 m/s);
- walking sideways at ±0.05 m/s (no forward speed);
- turning at ±0.3 rad/s (0.2 m/s);
- a push of 10, 20 or 30 N for 0.1 s on the torso, in eight directions (±x, ±y and the
  diagonals between them), at four phases of a step (0, ¼, ½, ¾ of the step after the start
  of the seventh step);
- a sensor fault in the middle of the walk (:data:`~zmpkit.experiments.walk_disturbances.FAULTS`).

Those are the figures for paper B's robot. On another robot the matrix is scaled
(:func:`robustness_matrix`): every forward and sideways speed by the robot's walking speed
over 0.2 m/s, every push by its mass over paper B's robot's (the same push per kilogram:
the same change of CoM velocity), so that a small robot is not judged on walks and pushes
beyond its size.

:func:`run_case` walks it and reduces it to one :class:`RobustnessRow` (the columns of
``robustness.csv``). A fall is a fall: its metrics are None, never averaged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_disturbances import FAULTS, PUSH_DIRECTIONS, Push, SensorFault
from zmpkit.robots.robot import Robot

__all__ = [
    "NOMINAL_SPEED_MPS",
    "NOMINAL_STEP_S",
    "ROBUSTNESS_COLUMNS",
    "RobustnessCase",
    "RobustnessRow",
    "robustness_matrix",
    "run_case",
]

NOMINAL_SPEED_MPS = 0.2
"""Speed of every case that does not vary it [m/s]."""
NOMINAL_STEP_S = 0.5
"""Step duration of every case that does not vary it [s]."""
PUSH_STEP = 6
"""Pushes land in the seventh step (index 6) after walking starts [-]."""
PUSH_PHASES = (0.0, 0.25, 0.5, 0.75)
"""Phases of the step at which a push starts [-]."""
PUSH_FORCES_N = (10.0, 20.0, 30.0)
"""Push magnitudes [N], each for 0.1 s."""
FAULT_TIME_S = 5.0
"""When a transient sensor fault starts [s]."""

ROBUSTNESS_COLUMNS: tuple[str, ...] = (
    "controller", "speed_mps", "lateral_mps", "turn_rad_s", "step_duration_s", "push_n",
    "push_dir", "push_phase", "fault", "fell", "fall_time_s", "fall_kind", "speed_error_pct",
    "trunk_pitch_peak_hz", "trunk_pitch_peak_amplitude_rad", "adjusted_steps",
    "uncaptured_steps",
)  # fmt: skip
"""Columns of ``robustness.csv``, in order (the first nine name the case)."""


@dataclass(frozen=True)
class RobustnessCase:
    """One walk of the matrix (module docstring).

    Attributes:
        controller: the walking controller.
        speed_mps: forward speed [m/s].
        lateral_mps: leftward speed [m/s].
        turn_rad_s: yaw rate [rad/s].
        step_duration_s: [s].
        push_n: push force [N] (0: none).
        push_dir: push direction (one of
            :data:`~zmpkit.experiments.walk_disturbances.PUSH_DIRECTIONS`; empty without a push).
        push_phase: phase of the step at which the push starts [-].
        fault: sensor fault (empty: none).
    """

    controller: str
    speed_mps: float = NOMINAL_SPEED_MPS
    lateral_mps: float = 0.0
    turn_rad_s: float = 0.0
    step_duration_s: float = NOMINAL_STEP_S
    push_n: float = 0.0
    push_dir: str = ""
    push_phase: float = 0.0
    fault: str = ""

    @property
    def label(self) -> str:
        """A short name, e.g. ``push 20 N -y @ 0.25`` (``zmpkit walk sweep --cases``)."""
        if self.push_n > 0.0:
            return f"push {self.push_n:g} N {self.push_dir} @ {self.push_phase:g}"
        if self.fault:
            return f"fault {self.fault}"
        if self.lateral_mps:
            return f"lateral {self.lateral_mps:g} m/s"
        if self.turn_rad_s:
            return f"turn {self.turn_rad_s:g} rad/s"
        return f"{self.speed_mps:g} m/s, {self.step_duration_s:g} s steps"

    @property
    def key(self) -> tuple[str, ...]:
        """The case as the first nine cells of its CSV row (for resuming)."""
        return tuple(_cell(getattr(self, name)) for name in ROBUSTNESS_COLUMNS[:9])

    def walk_config(
        self,
        robot: Robot,
        effects: str,
        duration_s: float,
        seed: int,
        step_adjustment: bool = False,
    ) -> WalkConfig:
        """The walk of this case on ``robot`` (``step_adjustment``: the walk moves its steps)."""
        pushes: tuple[Push, ...] = ()
        if self.push_n > 0.0:
            probe = WalkConfig(
                robot=robot, step_duration_s=self.step_duration_s, speed_mps=self.speed_mps
            )
            start = probe.pattern_config().plan().walk_start_s
            when = start + (PUSH_STEP + self.push_phase) * self.step_duration_s
            pushes = (Push(self.push_n, when, self.push_dir),)
        faults = (SensorFault(self.fault, FAULT_TIME_S),) if self.fault else ()
        return WalkConfig(
            robot=robot,
            speed_mps=self.speed_mps,
            lateral_speed_mps=self.lateral_mps,
            turn_rate_rps=self.turn_rad_s,
            step_duration_s=self.step_duration_s,
            duration_s=duration_s,
            effects=effects,
            seed=seed,
            controller=self.controller,
            pushes=pushes,
            faults=faults,
            figures=False,
            step_adjustment=step_adjustment,
        )


@dataclass(frozen=True)
class RobustnessRow:
    """What one case gave (the columns of ``robustness.csv``).

    Attributes:
        case: the walk.
        fell: whether it fell (tilt, torso height or stall).
        fall_time_s: when [s], or None.
        fall_kind: ``roll``, ``pitch``, ``height``, ``stall``, or None.
        speed_error_pct: mean forward speed against commanded, 100 (v - v_c)/v_c [%]; None
            after a fall or without a forward command.
        trunk_pitch_peak_hz: the trunk-pitch spectrum's peak [Hz]; None after a fall.
        trunk_pitch_peak_amplitude_rad: its amplitude [rad]; None after a fall.
        adjusted_steps: steps the walk moved to capture its DCM.
        uncaptured_steps: of them, those no admissible step could capture.
    """

    case: RobustnessCase
    fell: bool
    fall_time_s: float | None
    fall_kind: str | None
    speed_error_pct: float | None
    trunk_pitch_peak_hz: float | None
    trunk_pitch_peak_amplitude_rad: float | None
    adjusted_steps: int = 0
    uncaptured_steps: int = 0

    def cells(self) -> list[str]:
        """The CSV row, in :data:`ROBUSTNESS_COLUMNS` order (empty cell for None)."""
        values = (
            self.fell, self.fall_time_s, self.fall_kind, self.speed_error_pct,
            self.trunk_pitch_peak_hz, self.trunk_pitch_peak_amplitude_rad, self.adjusted_steps,
            self.uncaptured_steps,
        )  # fmt: skip
        return [*self.case.key, *(_cell(v) for v in values)]


def _cell(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def robustness_matrix(
    controllers: tuple[str, ...], speed_scale: float = 1.0, push_scale: float = 1.0
) -> list[RobustnessCase]:
    """Every case of the module docstring for each controller (116 per controller).

    Args:
        controllers: the walking controllers.
        speed_scale: the robot's walking speed over :data:`NOMINAL_SPEED_MPS` [-]; it scales
            every forward and sideways speed (rounded to 0.1 mm/s).
        push_scale: the robot's mass over paper B's robot's [-]; it scales every push
            (rounded to 0.01 N).
    """
    speed = [round(v * speed_scale, 4) for v in (0.05, 0.10, 0.15, 0.20, 0.25, 0.30)]
    nominal = round(NOMINAL_SPEED_MPS * speed_scale, 4)
    sideways = round(0.05 * speed_scale, 4)
    forces = [round(f * push_scale, 2) for f in PUSH_FORCES_N]
    cases: list[RobustnessCase] = []
    for c in controllers:
        cases += [RobustnessCase(c, speed_mps=v) for v in speed]
        cases += [
            RobustnessCase(c, speed_mps=nominal, step_duration_s=s)
            for s in (0.35, 0.40, 0.45, 0.55, 0.60, 0.70)
        ]
        cases += [RobustnessCase(c, speed_mps=0.0, lateral_mps=v) for v in (sideways, -sideways)]
        cases += [RobustnessCase(c, speed_mps=nominal, turn_rad_s=w) for w in (0.3, -0.3)]
        cases += [
            RobustnessCase(c, speed_mps=nominal, push_n=f, push_dir=d, push_phase=p)
            for f in forces
            for d in PUSH_DIRECTIONS
            for p in PUSH_PHASES
        ]
        cases += [RobustnessCase(c, speed_mps=nominal, fault=fault) for fault in FAULTS]
    return cases


def run_case(
    case: RobustnessCase,
    robot: Robot,
    effects: str,
    duration_s: float,
    seed: int,
    step_adjustment: bool = False,
) -> RobustnessRow:
    """Walk ``case`` on ``robot`` and reduce it to its row."""
    config = case.walk_config(robot, effects, duration_s, seed, step_adjustment)
    summary = run_walk_trial(config).summary
    error = None
    if summary.mean_speed_mps is not None and abs(case.speed_mps) > 0.0 and not case.turn_rad_s:
        error = 100.0 * (summary.mean_speed_mps - case.speed_mps) / case.speed_mps
    amplitude = summary.trunk_pitch_peak_amplitude_rad
    return RobustnessRow(
        case, summary.fell, summary.fall_time_s, summary.fall_kind,
        None if error is None or not math.isfinite(error) else error,
        summary.trunk_pitch_peak_hz, amplitude, summary.adjusted_steps, summary.uncaptured_steps,
    )  # fmt: skip
