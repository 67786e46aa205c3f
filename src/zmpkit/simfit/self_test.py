r"""Self-test of the simulator fit: a virtual robot with hidden, perturbed truth.

1. :func:`perturbed_values`: every fitted parameter moves from its nominal value by a
   factor :math:`e^{\pm u}`, :math:`u \sim U(\ln 1.08, \ln 1.25)` with a random sign
   (linear parameters by ±8–25 % of their bounds' range), drawn from the seed and kept
   inside the bounds. These values are the hidden truth.
2. :func:`record_experiments`: the virtual robot with that truth and the sensor effects on
   (S: encoder quantisation, F-T offsets, noise) runs the plan's experiments through the
   ordinary pipelines — walks with :func:`~zmpkit.experiments.walk.run_walk_trial` or step
   sweeps with :func:`~zmpkit.experiments.run_step_sweep`, as the robot's fit replays them
   (:attr:`~zmpkit.robots.robot.FitSpec.experiment`) — into folders. The fit then
   reads those folders like any recorded data and never sees the truth.
3. :func:`recovery_rows` compares truth and fit per parameter (``recovery.csv``).

Plans (:func:`self_test_plan`): walks at several speeds, or ZMP steps; with ``designed``,
also the designed double-support experiments (:mod:`zmpkit.experiments.double_support`:
a crouch held, a squat, a sagittal chirp sway, a frontal sway), recorded from the truth as
a real robot runs their protocol
(:func:`~zmpkit.experiments.double_support_record.record_double_support`) and fitted beside
the walks or steps. Held-out experiments are recorded the same way but
never fitted.
"""

from __future__ import annotations

import hashlib
import math
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.experiments import StepExperimentConfig, run_step_sweep
from zmpkit.experiments.double_support import DESIGNS, double_support_targets
from zmpkit.experiments.double_support_record import record_double_support
from zmpkit.experiments.walk import run_walk_trial
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_dataset import write_walk_folder
from zmpkit.robots.robot import Robot
from zmpkit.simfit.parameters import FitParameter
from zmpkit.simfit.truth_doc import truth_doc_with, write_truth_doc

__all__ = [
    "RECOVERY_COLUMNS",
    "RecoveryRow",
    "SelfTestPlan",
    "perturbed_values",
    "record_experiments",
    "recovery_rows",
    "self_test_plan",
    "write_recovery_csv",
]

RECOVERY_COLUMNS = ("parameter", "truth", "fitted", "error_pct", "identifiable")
"""Columns of ``recovery.csv``, in order."""
_PERTURB_RANGE = (math.log(1.08), math.log(1.25))


@dataclass(frozen=True)
class SelfTestPlan:
    """The experiments of a self-test.

    Attributes:
        fit: walks: (speed [m/s], duration [s]) per walk; steps: ZMP targets [m] of one sweep.
        held_out: the same for the held-out experiments.
        hold_s: steps only: recorded time after the step [s].
        held_out_hold_s: steps only: recorded time after the held-out step [s].
        designs: designed double-support experiments fitted too
            (:data:`~zmpkit.experiments.double_support.DESIGNS`).
    """

    fit: tuple
    held_out: tuple
    hold_s: float = 3.0
    held_out_hold_s: float = 8.0
    designs: tuple[str, ...] = ()


def self_test_plan(robot: Robot, quick: bool, designed: bool = False) -> SelfTestPlan:
    """The plan for ``robot``; ``quick`` keeps it small (2 short walks or 3 steps).

    Step targets are shares of the robot's largest balance target
    (:attr:`~zmpkit.robots.robot.BalanceModel.max_target_m`). ``designed`` adds every
    designed double-support experiment to the fitted ones.
    """
    designs = tuple(DESIGNS) if designed else ()
    if _replays_walks(robot):
        if quick:
            return SelfTestPlan(((0.2, 3.0), (0.15, 3.0)), ((0.175, 10.0),), designs=designs)
        return SelfTestPlan(
            ((0.1, 6.0), (0.15, 6.0), (0.2, 6.0)), ((0.175, 10.0), (0.2, 10.0)), designs=designs
        )
    span = robot.require_balance().max_target_m
    if quick:
        return SelfTestPlan(_shares((0.2, 0.5, 0.8), span), _shares((0.65,), span), designs=designs)
    return SelfTestPlan(
        _shares((0.2, 0.4, 0.6, 0.8), span),
        _shares((0.3, 0.7), span),
        hold_s=5.0,
        designs=designs,
    )


def _shares(shares: tuple[float, ...], span_m: float) -> tuple[float, ...]:
    """Step targets at ``shares`` of the robot's largest balance target ``span_m`` [m]."""
    return tuple(round(share * span_m, 6) for share in shares)


def _replays_walks(robot: Robot) -> bool:
    return robot.require_fit().experiment == "walk"


def perturbed_values(parameters: tuple[FitParameter, ...], seed: int) -> NDArray[np.float64]:
    """The hidden truth: nominal values moved 8–25 % by ``seed`` (module docstring) [units]."""
    rng = np.random.default_rng([seed, 7])
    out = []
    for p in parameters:
        u = rng.uniform(*_PERTURB_RANGE) * rng.choice((-1.0, 1.0))
        if p.log_scale:
            value = p.nominal * math.exp(u)
        else:
            value = p.nominal + math.copysign(math.expm1(abs(u)), u) * (p.upper - p.lower)
        out.append(min(max(value, p.lower), p.upper))
    return np.array(out)


def _walks(
    robot: Robot, specs: tuple, truth: Path, effects: str, seed: int, out: Path
) -> list[Path]:

    folders = []
    for k, (speed, duration) in enumerate(specs):
        folder = out / f"walk_{speed:g}mps_{duration:g}s"
        config = WalkConfig(
            robot=robot,
            speed_mps=speed,
            duration_s=duration,
            effects=effects,
            seed=seed + k,
            truth=str(truth),
            figures=False,
        )
        trial = run_walk_trial(config)
        joints = robot.require_walking().series_joints
        folders.append(
            write_walk_folder(folder, trial.summary, trial.pattern, trial.record, joints)
        )
    return folders


def _steps(
    robot: Robot, targets: tuple, hold_s: float, truth: Path, effects: str, seed: int, out: Path
) -> Path:

    config = StepExperimentConfig(
        robot=robot,
        targets_m=tuple(targets),
        effects=effects,
        seed=seed,
        settle_s=2.0,
        hold_s=hold_s,
        truth=str(truth),
    )
    return Path(run_step_sweep(config, out, workers=1).path)


def record_experiments(
    robot: Robot,
    plan: SelfTestPlan,
    base_doc: dict,
    parameters: tuple[FitParameter, ...],
    truth_values: NDArray[np.float64],
    effects: str,
    seed: int,
    out: Path,
) -> tuple[list[Path], list[Path]]:
    """Record the plan's fit and held-out experiments from the hidden truth into ``out``.

    The truth file is written into a temporary folder named after the truth's content, so a
    run resumed (or repeated with the same seed) names the same truth in its datasets'
    settings and finds its recordings complete. The folder is left in place (one small YAML
    file per truth): another process recording the same truth at the same time (parallel
    test workers, two self-tests of one seed) reads the same path, and removing it after one
    run pulled it from under the other ("truth file not found").

    Returns:
        (fit folders, held-out folders).
    """
    recorded = "S" if effects == "none" else f"{effects},S"
    doc = truth_doc_with(base_doc, parameters, truth_values)
    digest = hashlib.sha256(yaml.safe_dump(doc, sort_keys=True).encode()).hexdigest()[:16]
    hidden = Path(tempfile.gettempdir()) / f"zmpkit-hidden-truth-{digest}"
    hidden.mkdir(exist_ok=True)
    truth = write_truth_doc(doc, hidden / "truth.yaml")
    designed = _designs(robot, plan.designs, truth, recorded, seed + 200, out / "designed")
    if _replays_walks(robot):
        fit = _walks(robot, plan.fit, truth, recorded, seed, out / "fit")
        held = _walks(robot, plan.held_out, truth, recorded, seed + 100, out / "held_out")
        return [*fit, *designed], held
    fit_dir = _steps(robot, plan.fit, plan.hold_s, truth, recorded, seed, out / "fit_steps")
    held_dir = _steps(
        robot,
        plan.held_out,
        plan.held_out_hold_s,
        truth,
        recorded,
        seed + 100,
        out / "held_out_steps",
    )
    return [fit_dir, *designed], [held_dir]


def _designs(
    robot: Robot, designs: tuple[str, ...], truth: Path, effects: str, seed: int, out: Path
) -> list[Path]:
    """Record each designed double-support experiment from the truth into ``out/<name>``.

    Raises:
        ParameterError: when the truth cannot run one (it fell or diverged): a self-test
            whose truth cannot stand in double support has nothing to fit there.
    """
    folders = []
    for k, name in enumerate(designs):
        folder = out / name
        targets = double_support_targets(robot, name)
        written = record_double_support(robot, targets, effects, str(truth), seed + k, folder)
        if written is None:
            raise ParameterError(
                f"the self-test's hidden truth (seed {seed - 200}) fell or diverged in the "
                f"designed experiment {name!r}; try another --seed"
            )
        folders.append(written)
    return folders


@dataclass(frozen=True)
class RecoveryRow:
    """One parameter: hidden truth vs fitted value.

    Attributes:
        parameter: its name.
        truth: hidden value [unit].
        fitted: fitted value [unit].
        error_pct: 100 (fitted − truth) / truth [%].
        identifiable: whether the data pin it down (profile test).
    """

    parameter: str
    truth: float
    fitted: float
    error_pct: float
    identifiable: bool


def recovery_rows(
    parameters: tuple[FitParameter, ...], truth: NDArray, fitted: NDArray, identifiable: list[bool]
) -> list[RecoveryRow]:
    """Truth vs fit per parameter."""
    return [
        RecoveryRow(p.name, float(t), float(f), 100.0 * (f - t) / t if t else math.nan, ok)
        for p, t, f, ok in zip(parameters, truth, fitted, identifiable, strict=True)
    ]


def write_recovery_csv(rows: list[RecoveryRow], path: Path) -> Path:
    """Write ``recovery.csv`` with exactly :data:`RECOVERY_COLUMNS`."""
    lines = [",".join(RECOVERY_COLUMNS)]
    lines += [
        f"{r.parameter},{r.truth:.8g},{r.fitted:.8g},{r.error_pct:.4g},"
        f"{str(r.identifiable).lower()}"
        for r in rows
    ]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
