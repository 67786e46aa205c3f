"""Replicas through the data's pipeline: a ``zmpkit walk`` log walked again and re-cut.

The reference is the recorded walk itself: a replica recorded by the very truth that
walked, with the walk's controller and the window cutting of the fit, must give windows
of the same rows and commands alike to within the closed loop's answer to other noise.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from zmpkit.cli.app import main
from zmpkit.experiments.walk_log import WALK_LOG_FILE
from zmpkit.robots.registry import get_robot
from zmpkit.simfit.experiments import read_experiments, simulated_effects
from zmpkit.simfit.parameters import default_parameters
from zmpkit.simfit.pipeline_replicas import pipeline_replica, walk_settings
from zmpkit.simfit.problem import FitProblem
from zmpkit.simfit.refit_intervals import refit_intervals
from zmpkit.simfit.shooting_window import ShootingWindow
from zmpkit.simfit.truth_doc import base_truth_path, load_truth_doc

NAO = get_robot("nao")
PARAMS = default_parameters(NAO, "M,G", ("pid_gain_scale", "gear_stiffness"))


@pytest.fixture(scope="module")
def walk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 3 s ``zmpkit walk`` folder (zmpip, M, G, S, shipped truth) holding its log."""
    out = tmp_path_factory.mktemp("walk") / "walk"
    argv = ["walk", "--robot", "nao", "--duration", "3", "--effects", "M,G,S", "--no-video"]
    assert main([*argv, "--report", "md", "--seed", "3", "--out", str(out)]) == 0
    return out


def _problem(paths: list[Path]) -> FitProblem:
    experiments = read_experiments(paths, NAO)
    base = load_truth_doc(base_truth_path(NAO, None))
    effects = simulated_effects("M,G,S", experiments)
    return FitProblem(NAO, effects, PARAMS, base, tuple(experiments))


@pytest.mark.slow
def test_a_replica_is_the_walk_again_cut_into_the_same_windows(walk: Path, tmp_path) -> None:
    problem = _problem([walk / WALK_LOG_FILE])
    settings = walk_settings(problem)
    assert settings is not None
    ((source, walked),) = settings.items()
    assert source == str(walk / WALK_LOG_FILE)
    assert walked.controller == "zmpip"
    assert walked.effects == "M,G,S"
    nominal = [p.nominal for p in PARAMS]
    replica = pipeline_replica(problem, nominal, 0, settings)
    assert replica is not None
    data = [w for w in problem.experiments if isinstance(w, ShootingWindow)]
    again = [w for w in replica.experiments if isinstance(w, ShootingWindow)]
    assert [w.name for w in again] == [w.name for w in data]
    for a, d in zip(again, data, strict=True):
        np.testing.assert_allclose(a.signals.time_s, d.signals.time_s, atol=1e-9)
        # its own measured start: the replica's F-T sensors read their own noise; its
        # encoders differ by the closed loop's answer to that noise, not by a step (they
        # may read alike: the NAO's encoders resolve 1.53 mrad)
        assert np.max(np.abs(a.start.wrenches - d.start.wrenches)) > 0.0
        assert np.max(np.abs(a.start.q_rad - d.start.q_rad)) < 0.05
    # a log with no zmpkit walk beside it cannot be walked again: its windows are replayed
    alone = tmp_path / "alone.csv"
    alone.write_bytes((walk / WALK_LOG_FILE).read_bytes())
    assert walk_settings(_problem([alone])) is None
    intervals = refit_intervals(_problem([alone]), nominal, 2)
    assert intervals is not None
    for interval in intervals:
        assert interval.kind == "window_refits"
        assert interval.replicas == 2
        assert "replaying the log's commands" in interval.method
        assert interval.lower < interval.corrected < interval.upper


@pytest.mark.slow
def test_the_intervals_of_a_walk_log_are_bias_corrected_refits(walk: Path) -> None:
    problem = _problem([walk / WALK_LOG_FILE])
    nominal = [p.nominal for p in PARAMS]
    done: list[int] = []
    intervals = refit_intervals(problem, nominal, 2, progress=lambda k, n: done.append(k))
    assert intervals is not None
    assert done == [1, 2]
    for interval, value in zip(intervals, nominal, strict=True):
        assert interval.kind == "pipeline_refits"
        assert interval.replicas == 2
        assert math.isfinite(interval.bias)
        assert math.isfinite(interval.half_width)
        assert interval.lower < interval.corrected < interval.upper
        assert interval.value == value


@pytest.mark.slow
def test_replicas_on_two_processes_give_the_same_intervals(walk: Path) -> None:
    problem = _problem([walk / WALK_LOG_FILE])
    nominal = [p.nominal for p in PARAMS]
    done: list[int] = []
    serial = refit_intervals(problem, nominal, 2)
    pooled = refit_intervals(problem, nominal, 2, lambda k, n: done.append(k), workers=2)
    assert serial is not None
    assert pooled is not None
    assert sorted(done) == [1, 2]
    assert [i.moves for i in pooled] == [i.moves for i in serial]
