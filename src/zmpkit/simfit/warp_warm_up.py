"""Compile, ahead of a fit, every MuJoCo Warp kernel the fit's ``warp`` backend uses.

A fit on MuJoCo Warp compiles its kernels on first use (minutes on a fresh machine: the
physics step is generated per robot model). :func:`warm_up_warp` runs one tiny batched
rollout per robot (a walk and a step trial run the same model, so the same kernels) the
way the fit runs them, so that the kernels land in the persistent kernel cache
(:mod:`zmpkit.sim.warp_cache`) and the fit, or any later run on this machine, loads them.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.robots.robot import Robot
from zmpkit.sim.warp_cache import cache_file_count
from zmpkit.simfit.warp_batched import WARP_RECORDS

__all__ = ["WARM_UP_STEPS", "WarmUpResult", "WarmedRobot", "warm_up_warp"]

WARM_UP_STEPS = 4
"""Physics steps of each warm-up rollout (enough to run every kernel once)."""
_WORLDS = 2


@dataclass(frozen=True)
class WarmedRobot:
    """One robot's warm-up rollout.

    Attributes:
        robot: the robot's name.
        seconds: wall time of its rollout, compilation or cache load included [s].
        skipped: why it was not run on MuJoCo Warp (a model feature Warp lacks), or None.
    """

    robot: str
    seconds: float
    skipped: str | None = None


@dataclass(frozen=True)
class WarmUpResult:
    """What a warm-up did.

    Attributes:
        cache_dir: Warp's kernel cache folder (its version folder included).
        device: the Warp device the kernels were compiled for, e.g. ``"cuda:0"``, ``"cpu"``.
        robots: one entry per robot, in the order asked.
        seconds: wall time of the whole warm-up, Warp's start included [s].
        files_before: files in the kernel cache before.
        files_after: files in the kernel cache after (the same on a second warm-up).
    """

    cache_dir: str
    device: str
    robots: tuple[WarmedRobot, ...]
    seconds: float
    files_before: int
    files_after: int


def warm_up_warp(robots: Sequence[Robot], effects: str, device: str | None) -> WarmUpResult:
    """Compile (or load from the kernel cache) the kernels a fit of ``robots`` uses.

    Args:
        robots: the robots (each with a fit catalogue).
        effects: effect letters the fit's simulator runs with, e.g. ``"M,G,S"`` (MuJoCo
            Warp needs the M effect: it has no PID servo).
        device: Warp device (``"cuda:0"``, ``"cpu"``); ``None`` is Warp's default.

    Raises:
        ParameterError: MuJoCo Warp is not installed (the message says how to install it),
            a robot without a fit catalogue, or an unknown device.
    """
    start = time.perf_counter()
    from zmpkit.sim.warp_batch import rollout_warp, warp_runtime

    try:
        wp, name = warp_runtime(device)
    except ModuleNotFoundError as exc:
        raise ParameterError(str(exc)) from None
    cache_dir = str(wp.config.kernel_cache_dir)
    before = cache_file_count(cache_dir)
    done = []
    for robot in robots:
        robot.require_fit()
        sim = robot.make_simulation(effects, None, seed=0)
        full = mujoco.mjtState.mjSTATE_FULLPHYSICS
        state = np.empty(mujoco.mj_stateSize(sim.model, full))
        mujoco.mj_getState(sim.model, sim.data, state, full)
        control = np.tile(sim.data.ctrl, (WARM_UP_STEPS, 1))
        t0 = time.perf_counter()
        try:  # recorded as the fit records (batched.py): some rows, no full state
            rollout_warp(
                [sim.model] * _WORLDS,
                state,
                control,
                device=name,
                record_steps=[1, WARM_UP_STEPS],
                record=WARP_RECORDS,
            )
        except ParameterError as exc:
            done.append(WarmedRobot(robot.name, time.perf_counter() - t0, str(exc)))
            continue
        done.append(WarmedRobot(robot.name, time.perf_counter() - t0))
    return WarmUpResult(
        cache_dir,
        name,
        tuple(done),
        time.perf_counter() - start,
        before,
        cache_file_count(cache_dir),
    )
