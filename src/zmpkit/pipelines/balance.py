"""``zmpkit balance``: experiments → identification → controller → validation → report.

Paper A §4.1–4.6 on a (virtual) robot, per plane:

1. the classic LIPM step sweep (Fig. 9, 14): the dataset the identification reads exactly as
   it would read a real robot's recorded steps;
2. identification on the *fit* targets only (even targets by default): steady-state error
   model (eq. 13 or a model chosen by cross-validation) and transients → ``params.yaml``;
3. the gain-scheduled DLIPM (Fig. 19) and a single linear correction, each run on *every*
   target, so the schedule is also tested between the points it was fitted on; with
   ``dlipm_feedback`` also the LIPM and the DLIPM with a PI on the measured ZMP (LIPM+PID,
   DLIPM+feedback), whose F-T readings may carry injected faults (``faults``,
   :mod:`zmpkit.experiments.ft_faults`) behind a plausibility gate;
4. Table 1 and Fig. 16, 20, 21 → ``table1.csv``, figures and ``report.html``.

Every sweep is a resumable dataset folder under ``DIR/datasets/``: an interrupted run loses
no finished trial. Nothing here reads the robot's truth: only recorded sensors and design data
(mass, lean length from the design model, sole size, servo limits).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from zmpkit.analysis.balance_validation import ControllerOutcome, evaluate_trial
from zmpkit.analysis.table1 import Table1Row
from zmpkit.errors import ParameterError, ZmpkitError
from zmpkit.experiments import (
    StepExperimentConfig,
    dataset_trials,
    design_lean_model,
    lean_angle,
    run_step_sweep,
)
from zmpkit.experiments.ft_faults import FtFaults
from zmpkit.experiments.lean_controllers import FEEDBACK_KINDS, LeanControllerFactory
from zmpkit.experiments.sweep import check_sweep
from zmpkit.identify import BalanceIdentification, BalanceParams, ErrorModel, identify_balance
from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT, get_robot
from zmpkit.robots.robot import Robot
from zmpkit.signals import StepTrial

__all__ = [
    "FAST_TIME_SCALE",
    "FAST_ZETA",
    "FIT_TARGETS",
    "FULL_TARGETS",
    "MIN_CHOSEN_TARGETS",
    "QUICK_TARGETS",
    "BalanceConfig",
    "BalanceResult",
    "PlaneResult",
    "fit_targets_of",
    "run_balance",
    "step_experiment",
    "support_polygon",
    "target_ladder",
]

FULL_TARGETS = tuple(k / 10 for k in range(11))
"""The full sweep's targets, as shares of the robot's largest target [-]."""
QUICK_TARGETS = (0.0, 0.2, 0.3, 0.4, 0.6, 0.8, 0.9, 1.0)
"""A quick sweep's targets, as shares of the robot's largest target [-]."""
FIT_TARGETS = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0)
"""The fit's targets (the even ones of the full sweep), as shares of the largest target [-]."""
_ZETA = 0.8
FAST_TIME_SCALE = 2.0
"""The DLIPM's time scale of ``--dlipm-pace fast`` [-]: its plan asks 4–9× the servos'
acceleration limit at the step, which the servos' trajectory limiter clips, as it clips the
LIPM's step (``examples/balance_pacing.py``)."""
FAST_ZETA = 1.0
"""The DLIPM's damping ratio of ``--dlipm-pace fast`` [-]."""
_REACH_FRACTION = 0.3  # controllers lean at most to a ZMP of this fraction of l_lean [-]
_ProgressFactory = Callable[[str, int], Callable[[int, int, float], None]]


@dataclass(frozen=True)
class BalanceConfig:
    """Settings of one balance run.

    Attributes:
        robot: the robot (it needs a balance model); a registry name or ``robot.yaml`` path
            is resolved once, on creation.
        planes: planes to run, ``"sagittal"`` and/or ``"frontal"``; empty: every plane the
            robot can lean in (:attr:`~zmpkit.robots.robot.BalanceModel.planes`).
        targets_m: validation targets [m]; the fit uses those in ``fit_targets_m``; empty:
            :data:`FULL_TARGETS` of the robot's largest target
            (:attr:`~zmpkit.robots.robot.BalanceModel.max_target_m`, inside its support
            polygon).
        fit_targets_m: targets whose LIPM steps the identification uses [m]; empty:
            :data:`FIT_TARGETS` of the robot's largest target.
        effects: effects of the virtual robot (``"all"``, ``"none"``, letters).
        seed: sensor-noise seed.
        hold_s: recorded time after each step [s], the shortest hold.
        max_hold_s: holds are extended until the measured ZMP settles (creep included), up
            to this [s]; None: fixed holds of ``hold_s``.
        zeta: damping ratio of the scheduled DLIPM [-].
        time_scale: the DLIPM's (minimum) time scale [-]; paper A ran √(180/π)
            (:data:`~zmpkit.control.PAPER_A_TIME_SCALE`).
        servo_paced: slow the DLIPM per target only as much as the servos' acceleration
            limit needs (``time_scale`` is then the minimum); False: the fixed time scale.
        truth: a truth file replacing the robot's shipped one (for the simulator only).
        workers: processes running trials in parallel.
        video: whether to record one step trial as a video (``step_trial.mp4``: the
            scheduled DLIPM at the largest target of the first plane, run once more).
        dlipm_feedback: also run LIPM+PID and DLIPM+feedback (a PI on the measured ZMP,
            :mod:`zmpkit.control.dlipm_feedback`), two more column groups of Table 1.
        faults: F-T fault kinds injected into the feedback controllers' readings
            (:data:`~zmpkit.experiments.ft_faults.FAULT_KINDS`); needs ``dlipm_feedback``.
    """

    robot: Robot = field(default_factory=lambda: get_robot(DEFAULT_BALANCE_ROBOT))
    planes: tuple[str, ...] = ()
    targets_m: tuple[float, ...] = ()
    fit_targets_m: tuple[float, ...] = ()
    effects: str = "all"
    seed: int = 0
    hold_s: float = 20.0
    max_hold_s: float | None = 60.0
    zeta: float = _ZETA
    time_scale: float = 1.0
    servo_paced: bool = True
    truth: str | None = None
    workers: int = 2
    video: bool = False
    dlipm_feedback: bool = False
    faults: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        robot = get_robot(self.robot, needs="balance")
        object.__setattr__(self, "robot", robot)
        balance = robot.require_balance()
        if not self.planes:
            object.__setattr__(self, "planes", balance.planes)
        for plane in self.planes:
            balance.require_plane(plane)
        span = balance.max_target_m
        if not self.targets_m:
            object.__setattr__(self, "targets_m", target_ladder(FULL_TARGETS, span))
        if not self.fit_targets_m:
            object.__setattr__(self, "fit_targets_m", target_ladder(FIT_TARGETS, span))
        object.__setattr__(self, "faults", tuple(dict.fromkeys(self.faults)))
        if self.faults and not self.dlipm_feedback:
            raise ParameterError(
                "--fault injects faults into what the ZMP feedback reads: it needs --dlipm-feedback"
            )
        if self.faults:
            FtFaults(self.faults)  # checks the kinds
        run = {round(x, 6) for x in self.targets_m}
        for x in self.fit_targets_m:
            if round(x, 6) not in run:
                raise ParameterError(
                    f"fit target {x:g} m is not among the targets "
                    f"{', '.join(f'{t:g}' for t in self.targets_m)} m; the fit uses their "
                    "LIPM steps"
                )

    @classmethod
    def quick(cls, **changes: Any) -> BalanceConfig:
        """Fewer targets and shorter holds; still fits on even targets, validates on all."""
        robot = changes.get("robot", DEFAULT_BALANCE_ROBOT)
        span = get_robot(robot, needs="balance").require_balance().max_target_m
        quick = {
            "targets_m": target_ladder(QUICK_TARGETS, span),
            "hold_s": 14.0,
            "max_hold_s": 45.0,
        }
        return cls(**{**quick, **changes})


@dataclass(frozen=True, eq=False)
class PlaneResult:
    """One plane: the identification, the controllers' factories and the Table 1 rows."""

    plane: str
    identification: BalanceIdentification
    factories: dict[str, LeanControllerFactory]
    rows: tuple[Table1Row, ...]
    lean_length_m: float


@dataclass(frozen=True, eq=False)
class BalanceResult:
    """What ``run_balance`` produced: per-plane results and the identified parameters.

    ``failed_planes``: plane → why it did not finish (the finished planes are reported).
    """

    config: BalanceConfig
    planes: dict[str, PlaneResult] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)
    failed_planes: dict[str, str] = field(default_factory=dict)

    def params(self, plane: str) -> BalanceParams:
        """The identified parameters of ``plane`` (pendulum length: its lean length)."""
        return self.planes[plane].identification.params


def run_balance(
    config: BalanceConfig,
    out_dir: str | Path,
    *,
    progress: _ProgressFactory | None = None,
    echo: Callable[[str], None] = print,
) -> BalanceResult:
    """Run every plane of ``config`` and write its outputs into ``out_dir``.

    Writes datasets, ``params.yaml``, ``table1.csv``, figures and the report into
    ``out_dir`` (created if missing). A plane that fails (its identification finds no error
    model, its simulation diverges) is recorded with why in ``failed_planes`` and the run
    goes on with the others.

    Raises:
        ZmpkitError: the first plane's error when no plane finishes.
    """
    started_s = time.time()
    for plane in config.planes:  # every plane's targets in reach before any work
        check_sweep(step_experiment(config, plane))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    planes = {}
    for plane, why in config.robot.require_balance().missing_planes.items():
        echo(f"{plane} plane: not run, the robot cannot lean in it ({why})")
    failed: dict[str, str] = {}
    first_error: ZmpkitError | None = None
    for plane in config.planes:
        echo(f"{plane} plane: LIPM steps, identification, DLIPM and linear validation")
        try:
            planes[plane] = _run_plane(config, plane, out, progress)
        except ZmpkitError as exc:
            echo(f"{plane} plane failed: {exc}")
            failed[plane] = str(exc)
            first_error = first_error or exc
    if not planes and first_error is not None:
        raise first_error
    return BalanceResult(config=config, planes=planes, started_s=started_s, failed_planes=failed)


def step_experiment(config: BalanceConfig, plane: str) -> StepExperimentConfig:
    """The step experiment every sweep of ``plane`` runs (targets [m], holds [s], effects)."""
    return StepExperimentConfig(
        robot=config.robot,
        targets_m=config.targets_m,
        plane=plane,
        effects=config.effects,
        seed=config.seed,
        hold_s=config.hold_s,
        max_hold_s=config.max_hold_s,
        truth=config.truth,
    )


def _run_plane(
    config: BalanceConfig, plane: str, out: Path, progress: _ProgressFactory | None
) -> PlaneResult:
    experiment = step_experiment(config, plane)
    lean_length = design_lean_model(config.robot, plane).lean_length_m
    lipm, lipm_ends = _outcomes(config, experiment, plane, "lipm", out, progress, None)
    fit_set = {round(x, 6) for x in config.fit_targets_m}
    fit_trials = [t for t in lipm if round(t.zmp_ref, 6) in fit_set]
    mass = config.robot.require_balance().mass_kg
    identification = identify_balance(fit_trials, mass=mass, com_height=lean_length)
    model = identification.params.plane(plane).error_model
    fit_range = identification.planes[plane].error_fit.fitted_range
    kinds = ("dlipm", "linear", *(FEEDBACK_KINDS if config.dlipm_feedback else ()))
    factories = {
        kind: _factory(kind, model, lean_length, plane, config, fit_range) for kind in kinds
    }
    faulty = replace(experiment, faults=config.faults)
    runs = {
        kind: _outcomes(
            config,
            faulty if kind in FEEDBACK_KINDS else experiment,
            plane,
            kind,
            out,
            progress,
            factories[kind],
        )
        for kind in factories
    }

    def outcome(kind: str, k: int) -> ControllerOutcome | None:
        if kind not in runs:
            return None
        return evaluate_trial(kind, runs[kind][0][k], *runs[kind][1][k])

    rows = tuple(
        Table1Row(
            plane=plane,
            zmp_ref=trial.zmp_ref,
            lipm=evaluate_trial("lipm", trial, *lipm_ends[k]),
            dlipm=evaluate_trial("dlipm", runs["dlipm"][0][k], *runs["dlipm"][1][k]),
            linear=evaluate_trial("linear", runs["linear"][0][k], *runs["linear"][1][k]),
            fitted_on=round(trial.zmp_ref, 6) in fit_set,
            fit_range_m=fit_range,
            lipm_pid=outcome("lipm_pid", k),
            dlipm_fb=outcome("dlipm_fb", k),
        )
        for k, trial in enumerate(lipm)
    )
    return PlaneResult(plane, identification, factories, rows, lean_length)


def _outcomes(
    config: BalanceConfig,
    experiment: StepExperimentConfig,
    plane: str,
    kind: str,
    out: Path,
    progress: _ProgressFactory | None,
    factory: LeanControllerFactory | None,
) -> tuple[list[StepTrial], list[tuple[str, str]]]:
    """The sweep's trials, and how each one's hold ended (kind, note)."""
    callback = progress(f"{plane} {kind.upper()}", len(experiment.targets_m)) if progress else None
    dataset = run_step_sweep(
        experiment,
        out / "datasets" / f"{plane}_{kind}",
        workers=config.workers,
        progress=callback,
        controller=factory,
    )
    return dataset_trials(dataset), [(r.hold_end, r.hold_note) for r in dataset.trials]


MIN_CHOSEN_TARGETS = 4
"""Fewest targets ``--targets`` may give: three to fit the error model on, one to validate."""


def fit_targets_of(targets_m: tuple[float, ...]) -> tuple[float, ...]:
    """The targets to fit on among chosen ones [m]: every other one and the largest.

    Sorted, the first, third, … target and the largest are fitted on; the others, between
    them, validate the schedule (as the built-in ladders do: fit on even shares, validate on
    all).

    Raises:
        ParameterError: on fewer than :data:`MIN_CHOSEN_TARGETS` distinct targets.
    """
    ordered = sorted({round(x, 6) for x in targets_m})
    if len(ordered) < MIN_CHOSEN_TARGETS:
        raise ParameterError(
            f"--targets needs at least {MIN_CHOSEN_TARGETS} distinct targets (three to fit the "
            f"error model on, one to validate it); got {len(ordered)}: "
            f"{', '.join(f'{x:g}' for x in ordered)} m"
        )
    return tuple(sorted({*ordered[0::2], ordered[-1]}))


def target_ladder(shares: tuple[float, ...], span_m: float) -> tuple[float, ...]:
    """Targets at ``shares`` of ``span_m``, rounded to the micrometre [m]."""
    return tuple(round(share * span_m, 6) for share in shares)


def support_polygon(plane: str, robot: Robot | str = DEFAULT_BALANCE_ROBOT) -> tuple[float, float]:
    """Double-support extent of ``robot``'s soles in ``plane``, from the design [m]."""
    low, high = get_robot(robot, needs="balance").require_balance().support_polygon_m[plane]
    return (low, high)


def _factory(
    kind: str,
    model: ErrorModel,
    lean_length: float,
    plane: str,
    config: BalanceConfig,
    fit_range: tuple[float, float],
) -> LeanControllerFactory:
    robot = config.robot
    return LeanControllerFactory(
        kind=kind,
        error_model=model,
        mass_kg=robot.require_balance().mass_kg,
        lean_length_m=lean_length,
        zeta=config.zeta,
        time_scale=config.time_scale,
        angle_limit_rad=lean_angle(_REACH_FRACTION * lean_length, lean_length),
        rate_limit_rad_s=robot.servo_limits.max_velocity,
        support_polygon=support_polygon(plane, robot),
        max_acceleration_rad_s2=_lean_acceleration_limit(robot) if config.servo_paced else None,
        fitted_range=fit_range,
    )


def _lean_acceleration_limit(robot: Robot) -> float:
    """The lean angle's acceleration limit from the robot's servo limits [rad/s²].

    Lean joints move by the lean angle, in the frontal plane about as much.
    """
    return robot.servo_limits.max_acceleration
