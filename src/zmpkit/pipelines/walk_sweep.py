"""``zmpkit walk sweep``: the robustness matrix of the walking controllers, resumable.

Every case of :func:`~zmpkit.experiments.robustness.robustness_matrix` is walked in a process
pool; each finished row is appended to ``robustness.csv`` at once, so an interrupted sweep
loses at most the walks in flight, and a rerun into the same folder walks only the cases not
yet in the file (rows of another configuration are refused: ``sweep.json`` records it).
:func:`~zmpkit.pipelines.walk_sweep_files.write_walk_sweep` adds two figures per controller
(every case; the pushes as a matrix), the counts of falls and the report.
``SweepConfig.cases`` walks a subset (e.g. the 30 N pushes) into the same folder.
"""

from __future__ import annotations

import csv
import json
import multiprocessing
import time
from collections.abc import Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass, field, fields
from pathlib import Path

from zmpkit import _validate
from zmpkit.errors import InputFileError, ParameterError
from zmpkit.experiments.robustness import (
    ROBUSTNESS_COLUMNS,
    RobustnessCase,
    RobustnessRow,
    robustness_matrix,
    run_case,
)
from zmpkit.pipelines.progress import StageCallback
from zmpkit.robots.registry import DEFAULT_WALK_ROBOT, get_robot
from zmpkit.robots.robot import DEFAULT_WALK_SPEED_MPS, Robot
from zmpkit.sim.effect_set import EffectSet
from zmpkit.walking.walk_controllers import CONTROLLERS

__all__ = ["SweepConfig", "SweepResult", "run_walk_sweep"]

CSV_FILE = "robustness.csv"
CONFIG_FILE = "sweep.json"


def _mass_kg(robot: Robot) -> float:
    """The robot's mass, its design model's [kg]."""
    return float(robot.ik_model().body_subtreemass[0])


@dataclass(frozen=True)
class SweepConfig:
    """A robustness sweep.

    Attributes:
        robot: the robot (it walks); a registry name or ``robot.yaml`` path is resolved
            once, on creation.
        controllers: the controllers to sweep.
        effects: the simulated effects.
        duration_s: walking time of each case [s].
        seed: sensor-noise seed.
        workers: parallel processes.
        step_adjustment: whether the feedback walks move their steps to capture the DCM.
        cases: walk only the cases whose label contains this text (empty: all); e.g.
            ``push 30`` (:attr:`~zmpkit.experiments.robustness.RobustnessCase.label`).
    """

    robot: Robot = field(default_factory=lambda: get_robot(DEFAULT_WALK_ROBOT))
    controllers: tuple[str, ...] = ("zmpip", "dcm", "open")
    effects: str = "all"
    duration_s: float = 10.0
    seed: int = 0
    workers: int = 2
    step_adjustment: bool = False
    cases: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "robot", get_robot(self.robot, needs="walking"))
        unknown = [c for c in self.controllers if c not in CONTROLLERS]
        if unknown or not self.controllers:
            raise ParameterError(
                f"controllers must be among {', '.join(CONTROLLERS)}; got {self.controllers!r}"
            )
        _validate.positive("SweepConfig.duration_s", self.duration_s, "s")
        if self.duration_s < 5.0:
            raise ParameterError(
                f"SweepConfig.duration_s must be >= 5 s (pushes land in the seventh step); "
                f"got {self.duration_s}"
            )
        if self.workers < 1:
            raise ParameterError(f"SweepConfig.workers must be >= 1; got {self.workers}")
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)

    def identity(self) -> dict[str, object]:
        """What must match for rows to be resumed (not the controllers, workers or cases).

        The robot is its :attr:`~zmpkit.robots.robot.Robot.source`.
        """
        skip = ("controllers", "workers", "cases")
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name not in skip}
        return {**out, "robot": self.robot.source}

    def full_matrix(self) -> list[RobustnessCase]:
        """The whole matrix, scaled to the robot's walking speed and mass.

        Both against paper B's robot's (:func:`~zmpkit.experiments.robustness.robustness_matrix`).
        """
        reference = get_robot(DEFAULT_WALK_ROBOT, needs="walking")
        speed_scale = self.robot.require_walking().speed_mps / DEFAULT_WALK_SPEED_MPS
        push_scale = _mass_kg(self.robot) / _mass_kg(reference)
        return robustness_matrix(self.controllers, speed_scale, push_scale)

    def matrix(self) -> list[RobustnessCase]:
        """The cases this sweep walks: the matrix, or those whose label holds ``cases``."""
        return [c for c in self.full_matrix() if self.cases in c.label]


@dataclass(frozen=True)
class SweepResult:
    """A finished sweep.

    Attributes:
        config: what was swept.
        rows: one row per finished case (this run's and earlier runs' into the folder), in the
            matrix's order.
        files: the files written, by role.
        started_s: when this run of the sweep started [s since the epoch].
    """

    config: SweepConfig
    rows: tuple[tuple[str, ...], ...]
    files: dict[str, Path] = field(default_factory=dict)
    started_s: float = field(default_factory=time.time)

    def falls(self, controller: str) -> tuple[int, int]:
        """(falls, cases) of ``controller``."""
        mine = [r for r in self.rows if r[0] == controller]
        return sum(r[ROBUSTNESS_COLUMNS.index("fell")] == "true" for r in mine), len(mine)


def _read_rows(path: Path) -> dict[tuple[str, ...], tuple[str, ...]]:
    if not path.exists():
        return {}
    with path.open(newline="", encoding="utf-8") as handle:
        reader = csv.reader(handle)
        header = next(reader, None)
        if header is None:
            return {}
        if tuple(header) != ROBUSTNESS_COLUMNS:
            raise InputFileError(path, "is not a robustness table of this zmpkit; remove it")
        return {tuple(row[:9]): tuple(row) for row in reader if len(row) == len(header)}


def _check_identity(out: Path, config: SweepConfig) -> None:
    path = out / CONFIG_FILE
    if path.exists():
        earlier = json.loads(path.read_text(encoding="utf-8"))
        if earlier != config.identity():
            raise InputFileError(
                path, f"holds another sweep ({earlier}); use another --out to sweep {config}"
            )
    path.write_text(json.dumps(config.identity(), indent=2) + "\n", encoding="utf-8")


def _finished(cases: list[RobustnessCase], config: SweepConfig) -> Iterator[RobustnessRow]:
    if config.workers <= 1:
        for case in cases:
            yield run_case(case, *_trial(config))
        return
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=config.workers, mp_context=context) as pool:
        pending: set[Future[RobustnessRow]] = {
            pool.submit(run_case, case, *_trial(config)) for case in cases
        }
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                yield future.result()


def _trial(config: SweepConfig) -> tuple[Robot, str, float, int, bool]:
    """What :func:`run_case` takes besides the case."""
    return config.robot, config.effects, config.duration_s, config.seed, config.step_adjustment


def run_walk_sweep(
    config: SweepConfig, out: Path, progress: StageCallback | None = None
) -> SweepResult:
    """Walk every case not yet in ``out/robustness.csv``, appending each row as it finishes.

    Args:
        config: the sweep.
        out: output folder (created); an earlier sweep's rows there are kept.
        progress: called with ("walks", finished, total).
    """
    started_s = time.time()
    cases = config.matrix()
    out.mkdir(parents=True, exist_ok=True)
    _check_identity(out, config)
    path = out / CSV_FILE
    done = _read_rows(path)
    todo = [c for c in cases if c.key not in done]
    new_file = not path.exists() or not done
    with path.open("w" if new_file else "a", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        if new_file:
            writer.writerow(ROBUSTNESS_COLUMNS)
            handle.flush()
        finished = len(cases) - len(todo)
        if progress is not None:
            progress("walks", finished, len(cases))
        for row in _finished(todo, config):
            cells = tuple(row.cells())
            writer.writerow(cells)
            handle.flush()
            done[cells[:9]] = cells
            finished += 1
            if progress is not None:
                progress("walks", finished, len(cases))
    every = config.full_matrix()  # the report shows every finished case
    rows = tuple(done[c.key] for c in every if c.key in done)
    return SweepResult(config, rows, {"robustness": path}, started_s)
