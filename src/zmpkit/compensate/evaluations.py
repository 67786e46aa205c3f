"""Simulated walks with an offset, run in a process pool and cached in a folder.

Each evaluation is one walk (:class:`WalkSpec`) with one offset (:class:`OffsetParameters`,
or none). Its metrics are written to ``cache_dir/<key>.json`` as soon as it finishes, the
key a hash of the walk and the offset, so an interrupted tuning loses no finished walk and a
rerun with the same folder reads them back instead of simulating again.
"""

from __future__ import annotations

import hashlib
import json
import multiprocessing
from collections.abc import Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

from zmpkit.compensate.evaluate import simulate_with_offset
from zmpkit.compensate.offsets import OffsetParameters, offset_in_world
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.robots.robot import Robot
from zmpkit.walking import generate_pattern

__all__ = ["DEFAULT_WORKERS", "Evaluation", "WalkSpec", "evaluate_all"]

DEFAULT_WORKERS = 2
"""Processes of the pool [-]."""


@dataclass(frozen=True)
class WalkSpec:
    """A walk used for tuning or validation.

    Attributes:
        speed_mps: commanded speed [m/s]; None: the robot's walking speed
            (:attr:`~zmpkit.robots.robot.WalkingDefaults.speed_mps`, set on creation).
        seed: sensor-noise seed.
        duration_s: walking time [s].
        effects: effect letters of the simulated robot.
        robot: the walking robot (keyword-only).
        step_duration_s: one step [s].
        controller: the walking controller.
        truth: a truth file for the simulated robot (another robot than the shipped one),
            or None.
        truth_label: what that truth changes, e.g. ``gear stiffness x1.3`` (for reports).
    """

    speed_mps: float | None = None
    seed: int = 0
    duration_s: float = 10.0
    effects: str = "all"
    robot: Robot = field(kw_only=True)
    step_duration_s: float = 0.5
    controller: str = "open"
    truth: str | None = None
    truth_label: str = ""

    def __post_init__(self) -> None:
        if self.speed_mps is None:
            walking = self.robot.require_walking()
            object.__setattr__(self, "speed_mps", walking.speed_mps)

    def as_dict(self) -> dict[str, Any]:
        """The walk as JSON-ready values, in field order; the robot is its source."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        out["robot"] = self.robot.source
        return out

    @property
    def commanded_speed_mps(self) -> float:
        """The commanded speed [m/s] (``speed_mps``, set on creation)."""
        assert self.speed_mps is not None  # set in __post_init__
        return self.speed_mps

    def walk_config(self) -> WalkConfig:
        """The walk as ``zmpkit walk`` runs it (no figures)."""
        return WalkConfig(
            speed_mps=self.speed_mps, seed=self.seed, duration_s=self.duration_s,
            effects=self.effects, figures=False, robot=self.robot,
            step_duration_s=self.step_duration_s, controller=self.controller, truth=self.truth,
        )  # fmt: skip

    @property
    def label(self) -> str:
        """Short name, e.g. ``0.2 m/s seed 1`` or ``0.25 m/s 0.55 s gear stiffness x1.3``."""
        text = f"{self.speed_mps:g} m/s"
        if self.step_duration_s != 0.5:
            text += f" {self.step_duration_s:g} s"
        if self.truth_label:
            text += f" {self.truth_label}"
        return f"{text} seed {self.seed}"


@dataclass(frozen=True)
class Evaluation:
    """Metrics of one walk with one offset.

    Attributes:
        walk: the walk.
        offset: the offset, or None for the uncompensated walk.
        step_peak_rad: trunk-pitch spectrum amplitude at the step frequency [rad].
        std_rad: trunk-pitch standard deviation over the steady walk [rad].
        largest_peak_hz: frequency of the largest spectral peak above 0.5 Hz [Hz].
        largest_peak_rad: its amplitude [rad].
        fell: whether the walk fell or diverged (metrics then penalised).
    """

    walk: WalkSpec
    offset: OffsetParameters | None
    step_peak_rad: float
    std_rad: float
    largest_peak_hz: float | None
    largest_peak_rad: float | None
    fell: bool


def _key(walk: WalkSpec, offset: OffsetParameters | None) -> str:
    payload = {"walk": walk.as_dict(), "offset": None if offset is None else offset.as_dict()}
    text = json.dumps(payload, sort_keys=True, default=lambda v: round(float(v), 10))
    return hashlib.sha1(text.encode()).hexdigest()[:20]


def _simulate(task: tuple[WalkSpec, OffsetParameters | None]) -> Evaluation:
    walk, offset = task
    config = walk.walk_config()
    zmp_offset = None
    if offset is not None:
        zmp_offset = offset_in_world(offset, generate_pattern(config.pattern_config()))
    outcome = simulate_with_offset(config, zmp_offset)
    summary = outcome.summary
    return Evaluation(
        walk, offset, outcome.step_peak_rad, outcome.std_rad,
        None if summary is None else summary.trunk_pitch_peak_hz,
        None if summary is None else summary.trunk_pitch_peak_amplitude_rad, outcome.fell,
    )  # fmt: skip


def _to_json(evaluation: Evaluation) -> str:
    data = {f.name: getattr(evaluation, f.name) for f in fields(evaluation)}
    data["walk"] = evaluation.walk.as_dict()
    data["offset"] = None if evaluation.offset is None else asdict(evaluation.offset)
    return json.dumps(data, indent=1) + "\n"


def _from_json(text: str, walk: WalkSpec) -> Evaluation:
    """The evaluation cached as ``text`` of ``walk`` (the walk its key was made of)."""
    data = json.loads(text)
    data.pop("walk")
    offset = data.pop("offset")
    if offset is not None:
        offset = OffsetParameters(**{**offset, "fourier_m": tuple(offset["fourier_m"])})
    return Evaluation(walk, offset, **data)


def evaluate_all(
    tasks: Sequence[tuple[WalkSpec, OffsetParameters | None]],
    cache_dir: Path | None = None,
    workers: int = DEFAULT_WORKERS,
) -> list[Evaluation]:
    """Evaluate every (walk, offset) pair, in order, reusing and filling ``cache_dir``."""
    results: dict[int, Evaluation] = {}
    todo = []
    for i, (walk, offset) in enumerate(tasks):
        path = None if cache_dir is None else Path(cache_dir) / f"{_key(walk, offset)}.json"
        if path is not None and path.is_file():
            results[i] = _from_json(path.read_text(encoding="utf-8"), walk)
        else:
            todo.append((i, path))
    if todo:
        _run(tasks, todo, results, workers)
    return [results[i] for i in range(len(tasks))]


def _run(
    tasks: Sequence[tuple[WalkSpec, OffsetParameters | None]],
    todo: list[tuple[int, Path | None]],
    results: dict[int, Evaluation],
    workers: int,
) -> None:
    """Simulate the tasks of ``todo`` (index, cache file), on ``workers`` processes."""
    for _, path in todo:
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
    if workers <= 1 or len(todo) == 1:
        done = ((i, path, _simulate(tasks[i])) for i, path in todo)
        _store(done, results)
        return
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [(i, path, pool.submit(_simulate, tasks[i])) for i, path in todo]
        _store(((i, path, f.result()) for i, path, f in futures), results)


def _store(
    done: Iterable[tuple[int, Path | None, Evaluation]], results: dict[int, Evaluation]
) -> None:
    """Keep each finished evaluation in ``results`` and its cache file."""
    for i, path, evaluation in done:
        results[i] = evaluation
        if path is not None:
            path.write_text(_to_json(evaluation), encoding="utf-8")
