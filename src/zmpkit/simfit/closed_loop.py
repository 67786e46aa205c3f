"""A walk recorded with one of zmpkit's controllers, re-simulated in closed loop.

A ``zmpkit walk`` folder says which controller walked (``summary.json``: ``controller``,
``effects``, ``seed``, the command, pushes, ``adjusted_steps``). Its commanded joint angles
are that controller's output — the plan corrected by feedback on the robot's own sensors —
so no open-loop replay reproduces them. The fit re-simulates the very controller instead,
for each candidate: the same :class:`~zmpkit.experiments.walk_config.WalkConfig`, pattern,
whole-body IK and :func:`~zmpkit.experiments.walk.walk_controller` that
:func:`~zmpkit.experiments.walk.run_walk_trial` built, in the candidate's simulation, so the
controller reads the candidate's sensors and its commands follow the candidate's motion.

What the controller is given comes from the recording, not from the candidate: its
settings — the servo feed-forward (on when the recorded walk had the motor effect on), the
observer's noise levels, heading feedback (``zmpkit walk`` always runs it), step
adjustment (on when the walk adjusted a step: a walk that ran with it but never adjusted a
step behaves as one without) — are those that ran.

**Sensor noise.** A candidate's closed loop reads its own simulated sensors. With sampled
readings they draw noise from seed ``recorded seed + 1`` (:data:`NOISE_SEED_OFFSET`), a
realisation independent of the recorded one: a real robot's fit cannot know the noise its
walk met, and a candidate replaying the recorded realisation would match a virtual robot's
walk at its truth bit for bit, an optimism no robot allows and a noise floor of zero. The
seed is the same for every candidate, so the cost stays a deterministic function of the
parameters. With expected readings (``--sensor-readings expected``) the loop reads noise-free
sensors. Either way the cost at the truth is the closed loop's noise floor, not zero
(:mod:`~zmpkit.simfit.adequacy`).

Only the serial path runs these rollouts (a controller is Python at every motion frame):
the ``local`` backend sends them to a process pool, the ``warp`` backend refuses them
(:mod:`~zmpkit.simfit.batch_backend`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.walk import walk_controller
from zmpkit.experiments.walk_config import WalkConfig
from zmpkit.experiments.walk_trial import Push, WalkRecord, simulate_walk
from zmpkit.robots.robot import Robot
from zmpkit.sim.world import Simulation
from zmpkit.walking import generate_pattern
from zmpkit.walking.ik import JointTrajectory, solve_walking_ik
from zmpkit.walking.pattern import WalkingPattern

__all__ = [
    "NOISE_SEED_OFFSET",
    "WalkSettings",
    "closed_loop_plan",
    "planned_references",
    "simulate_closed_loop",
]

NOISE_SEED_OFFSET = 1
"""A candidate's sensor-noise seed is the recorded walk's plus this (module docstring) [-]."""


@dataclass(frozen=True)
class WalkSettings:
    """What a recorded walk ran: its command and its controller (``summary.json``).

    Attributes:
        robot: the robot that walked.
        speed_mps: commanded forward speed [m/s].
        step_duration_s: step duration [s].
        duration_s: walking time of the pattern [s].
        com_height_m: CoM height of the pattern [m].
        controller: ``open``, ``zmpip`` or ``dcm``.
        effects: the effects the walk ran with (its controller's feed-forward depends on
            them).
        seed: the recorded walk's sensor-noise seed.
        lateral_speed_mps: commanded leftward speed [m/s].
        turn_rate_rps: commanded yaw rate [rad/s].
        pushes: the pushes, as ``FORCE_N@TIME_S:DIR``.
        step_adjustment: whether the controller moved steps.
    """

    robot: Robot
    speed_mps: float
    step_duration_s: float
    duration_s: float
    com_height_m: float
    controller: str = "open"
    effects: str = "all"
    seed: int = 0
    lateral_speed_mps: float = 0.0
    turn_rate_rps: float = 0.0
    pushes: tuple[str, ...] = ()
    step_adjustment: bool = False

    def walk_config(self) -> WalkConfig:
        """The :class:`WalkConfig` that ``zmpkit walk`` ran (no figures)."""
        return WalkConfig(
            robot=self.robot,
            speed_mps=self.speed_mps,
            step_duration_s=self.step_duration_s,
            duration_s=self.duration_s,
            effects=self.effects,
            seed=self.seed,
            com_height_m=self.com_height_m,
            figures=False,
            controller=self.controller,
            lateral_speed_mps=self.lateral_speed_mps,
            turn_rate_rps=self.turn_rate_rps,
            pushes=tuple(Push.parse(p) for p in self.pushes),
            step_adjustment=self.step_adjustment,
        )


@lru_cache(maxsize=32)
def _pattern(settings: WalkSettings) -> WalkingPattern:
    return generate_pattern(settings.walk_config().pattern_config())


@lru_cache(maxsize=16)
def closed_loop_plan(settings: WalkSettings) -> tuple[WalkingPattern, JointTrajectory]:
    """The pattern and IK trajectory of ``settings``' walk, as ``zmpkit walk`` made them.

    Cached per process: each worker plans a walk once.
    """
    robot = settings.robot
    pattern = _pattern(settings)
    return pattern, solve_walking_ik(pattern, robot.ik_model(), robot.ik_settings)


def planned_references(settings: WalkSettings) -> NDArray[np.float64]:
    """The plan's ZMP reference and CoM, world x and y, per frame ``(N, 4)`` [m].

    What the walk folder records as ``zmp_ref_x_m, zmp_ref_y_m, com_ref_x_m, com_ref_y_m``:
    they depend on the command and the pattern only, never on the controller or the robot.
    """
    pattern = _pattern(settings)
    return np.column_stack([pattern.zmp_reference_in_world, pattern.com_position_in_world[:, :2]])


def simulate_closed_loop(settings: WalkSettings, sim: Simulation) -> WalkRecord:
    """Walk ``sim`` (a fresh candidate simulation) with the recorded walk's controller.

    Returns:
        The record, ending at the fall if the candidate fell.
    """
    config = settings.walk_config()
    robot = config.robot
    pattern, trajectory = closed_loop_plan(settings)
    controller = walk_controller(config, robot, pattern, trajectory, robot.ik_model(), sim)
    return simulate_walk(sim, trajectory, controller=controller, pushes=config.pushes)
