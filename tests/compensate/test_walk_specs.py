"""The tuning and validation walks of ``walk compensate`` at the robot's own walking speed.

They were designed for paper B's NAO at 0.2 m/s; another robot gets every speed and speed
change scaled by its walking speed over 0.2 m/s, and ``--speed``/``--step-duration`` are
honoured. The NAO's walks are the ones the pipeline ran before the scaling, written out.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from zmpkit.cli import main
from zmpkit.compensate.evaluations import WalkSpec
from zmpkit.errors import ParameterError
from zmpkit.pipelines.walk_compensate import METHODS, CompensateConfig
from zmpkit.robots.op3 import preset
from zmpkit.robots.registry import get_robot

# (speed [m/s], step [s], seed, duration [s], truth label) of every walk, as the pipeline
# built them for the NAO before the speed scaling (CompensateConfig at commit 5dee448)
NAO_WALKS = {
    ("open", True): (
        [(0.2, 0.5, 0, 6.0, "")],
        [(0.15, 0.5, 1, 6.0, ""), (0.25, 0.5, 1, 6.0, "")],
    ),
    ("open", False): (
        [(0.2, 0.5, 0, 10.0, "")],
        [(0.2, 0.5, 1, 10.0, ""), (0.2, 0.5, 2, 10.0, ""), (0.15, 0.5, 1, 10.0, ""),
         (0.25, 0.5, 1, 10.0, "")],
    ),
    ("zmpip", True): (
        [(0.2, 0.5, 0, 6.0, ""), (0.15, 0.45, 0, 6.0, "")],
        [(0.25, 0.55, 1, 6.0, "gear.stiffness x1.3"), (0.12, 0.4, 2, 6.0, "gear.stiffness x0.7")],
    ),
    ("zmpip", False): (
        [(0.2, 0.5, 0, 10.0, ""), (0.15, 0.45, 0, 10.0, ""), (0.15, 0.5, 0, 10.0, ""),
         (0.2, 0.45, 0, 10.0, "")],
        [(0.25, 0.55, 1, 10.0, "gear.stiffness x1.3"), (0.12, 0.4, 2, 10.0, "gear.stiffness x0.7"),
         (0.22, 0.42, 3, 10.0, "gear.stiffness x0.85"),
         (0.17, 0.58, 4, 10.0, "gear.stiffness x1.15")],
    ),
}  # fmt: skip
# the same with --speed 0.25 --step-duration 0.55 --seed 2 (quick)
NAO_GIVEN_WALKS = {
    "open": (
        [(0.25, 0.55, 2, 6.0, "")],
        [(0.15, 0.55, 3, 6.0, ""), (0.25, 0.55, 3, 6.0, "")],
    ),
    "zmpip": (
        [(0.25, 0.55, 2, 6.0, ""), (0.2, 0.5, 2, 6.0, "")],
        [(0.3, 0.6, 3, 6.0, "gear.stiffness x1.3"), (0.17, 0.45, 4, 6.0, "gear.stiffness x0.7")],
    ),
}  # fmt: skip


def _rows(walks: tuple[WalkSpec, ...]) -> list[tuple[float | None, float, int, float, str]]:
    return [(w.speed_mps, w.step_duration_s, w.seed, w.duration_s, w.truth_label) for w in walks]


def _speeds(config: CompensateConfig) -> tuple[list[float | None], list[float | None]]:
    tuning, validation = config.tuning_walks(), config.validation_walks()
    return [w.speed_mps for w in tuning], [w.speed_mps for w in validation]


@pytest.mark.parametrize(("controller", "quick"), sorted(NAO_WALKS))
def test_the_nao_walks_are_unchanged(controller: str, quick: bool) -> None:
    config = CompensateConfig(method="half-sine", controller=controller, quick=quick)
    assert config.speed_mps == 0.2
    assert config.speed_scale == 1.0
    tuning, validation = NAO_WALKS[(controller, quick)]
    assert _rows(config.tuning_walks()) == tuning
    assert _rows(config.validation_walks()) == validation
    nao = get_robot("nao")
    assert all(w.robot is nao and w.controller == controller for w in config.tuning_walks())


@pytest.mark.parametrize("controller", sorted(NAO_GIVEN_WALKS))
def test_the_nao_walks_at_a_given_speed_and_step_are_unchanged(controller: str) -> None:
    config = CompensateConfig(
        method="half-sine", controller=controller, quick=True, speed_mps=0.25,
        step_duration_s=0.55, seed=2,
    )  # fmt: skip
    tuning, validation = NAO_GIVEN_WALKS[controller]
    assert _rows(config.tuning_walks()) == tuning
    assert _rows(config.validation_walks()) == validation


def test_a_walk_spec_without_a_speed_walks_at_its_robots_speed(tmp_path: Path) -> None:
    nao = get_robot("nao")
    assert WalkSpec(robot=nao).speed_mps == 0.2
    assert WalkSpec(speed_mps=0.2, robot=nao) == WalkSpec(robot=nao)
    robot = get_robot(_robot_walking_at(tmp_path, 0.12))
    assert WalkSpec(robot=robot).speed_mps == 0.12
    assert WalkSpec(robot=robot).walk_config().speed_mps == 0.12
    assert WalkSpec(robot=robot, speed_mps=0.05).walk_config().speed_mps == 0.05


def test_the_op3_tunes_and_validates_at_half_the_speeds() -> None:
    pytest.importorskip(preset.OP3_ASSETS_PACKAGE)
    open_loop = CompensateConfig(method="half-sine", robot="op3", controller="open", quick=True)
    assert open_loop.speed_mps == 0.1
    assert open_loop.speed_scale == 0.5
    assert _speeds(open_loop) == ([0.1], [0.075, 0.125])
    held_out = CompensateConfig(method="half-sine", robot="op3", controller="zmpip")
    assert _speeds(held_out) == ([0.1, 0.075, 0.075, 0.1], [0.125, 0.06, 0.11, 0.085])
    steps = [w.step_duration_s for w in held_out.validation_walks()]
    assert steps == [0.55, 0.4, 0.42, 0.58]  # step durations are not scaled


def test_a_user_robot_tunes_and_validates_at_its_own_speed(tmp_path: Path) -> None:
    robot = get_robot(_robot_walking_at(tmp_path, 0.12))
    open_loop = CompensateConfig(method="half-sine", robot=robot, controller="open")
    assert open_loop.speed_scale == pytest.approx(0.6)
    assert _speeds(open_loop) == ([0.12], [0.12, 0.12, 0.09, 0.15])
    held_out = CompensateConfig(method="half-sine", robot=robot, controller="zmpip", quick=True)
    assert _speeds(held_out) == ([0.12, 0.09], [0.15, 0.072])


@pytest.mark.parametrize("method", METHODS)
def test_a_given_speed_and_step_are_honoured_by_every_method(tmp_path: Path, method: str) -> None:
    robot = get_robot(_robot_walking_at(tmp_path, 0.12))
    controller = "zmpip" if method == "alg2" else "open"
    config = CompensateConfig(
        method=method, robot=robot, controller=controller, quick=True, speed_mps=0.14,
        step_duration_s=0.45,
    )  # fmt: skip
    first = config.tuning_walks()[0]
    assert (first.speed_mps, first.step_duration_s) == (0.14, 0.45)
    assert {w.step_duration_s for w in config.validation_walks()} <= {0.45, 0.5, 0.35}
    if controller == "open":
        assert _speeds(config)[1] == [0.09, 0.15]


def test_a_held_out_walk_too_slow_for_the_robot_is_named(tmp_path: Path) -> None:
    robot = get_robot(_robot_walking_at(tmp_path, 0.12))
    with pytest.raises(ParameterError, match=r"must be >= 0\.078 m/s .* go 0\.048 m/s slower"):
        CompensateConfig(robot=robot, controller="zmpip", speed_mps=0.07)
    with pytest.raises(ParameterError, match=r"must be >= 0\.13 m/s .* go 0\.08 m/s slower"):
        CompensateConfig(controller="zmpip", speed_mps=0.12)


def test_a_walk_outside_the_robots_step_range_is_named_before_tuning() -> None:
    with pytest.raises(ParameterError, match=r"the walk 0\.12 m/s 0\.15 s .*step_duration_s"):
        CompensateConfig(controller="zmpip", step_duration_s=0.25)


class _ReachedError(Exception):
    """Raised where the pipeline's work would start."""


def test_the_cli_tunes_at_the_robots_walking_speed(tmp_path: Path, monkeypatch) -> None:
    seen: list[CompensateConfig] = []

    def stop(config: CompensateConfig, *args: object, **kwargs: object) -> None:
        seen.append(config)
        raise _ReachedError

    monkeypatch.setattr("zmpkit.cli.walk.run_walk_compensate", stop)
    robot = _robot_walking_at(tmp_path, 0.12)
    out = str(tmp_path / "out")
    for given in ([], ["--speed", "0.1", "--step-duration", "0.6"]):
        with pytest.raises(_ReachedError):
            main(["walk", "compensate", "--robot", robot, *given, "--out", out])
    assert [(c.speed_mps, c.step_duration_s) for c in seen] == [(0.12, 0.5), (0.1, 0.6)]


def _robot_walking_at(folder: Path, speed_mps: float) -> str:
    """The test biped's robot.yaml (``robot init``) with ``walking.speed``."""
    from helpers.biped import BIPED_MJCF

    model = folder / "biped.xml"
    model.write_text(BIPED_MJCF, encoding="utf-8")
    out = folder / "robot.yaml"
    assert main(["robot", "init", str(model), "--out", str(out)]) == 0
    with out.open("a", encoding="utf-8") as handle:
        handle.write(f"walking: {{speed: {speed_mps}}}\n")
    return str(out)
