"""Many candidates of one experiment at once: open-loop rollouts on MuJoCo's thread pool.

Both kinds of experiment are open loop (:mod:`~zmpkit.simfit.open_loop`), so the
rollouts of a whole CMA-ES generation run in C on :class:`mujoco.batch.Batch` threads, a
second of simulated time per call, with no Python per physics step; Python then reads the
recorded rows (:mod:`~zmpkit.simfit.batch_rows`) as
:mod:`~zmpkit.simfit.rollout` reads the simulation step by step.

The results are those of the serial path (tested): each candidate's
:class:`~zmpkit.sim.world.Simulation` is built and posed as there, the batch continues from
its exact integration state (warm start included), the F-T channels draw the same noise
(:func:`~zmpkit.sim.sensing.sample_series`), and a fall or a divergence ends a rollout at
the same step:

- divergence: MuJoCo's bad-acceleration warning (the batch stops that simulation, so its
  time stops advancing) or a joint speed beyond
  :data:`~zmpkit.sim.world.DIVERGED_SPEED_RAD_S` at an F-T sample; a walk then has no
  signals, a step trial keeps the samples before it;
- a walk's fall: trunk tilt or torso height past the limits of
  :mod:`~zmpkit.experiments.walk_trial`; its record ends at that frame.

A candidate whose simulation raises another MuJoCo warning (which stops it in the batch but
not in the serial path) is re-run on the serial path. The rows are judged and read in
:mod:`~zmpkit.simfit.batch_reading`; the same rollouts on MuJoCo Warp are
:mod:`~zmpkit.simfit.warp_batched`'s.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import mujoco.batch
import numpy as np

from zmpkit.sim.world import Simulation
from zmpkit.simfit.batch_reading import ft_readings, layout_groups, read_candidates
from zmpkit.simfit.batch_rows import BatchRows
from zmpkit.simfit.experiments import Experiment
from zmpkit.simfit.open_loop import OpenLoopSchedule, open_loop_schedule, posed_simulations
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import simulate_experiment
from zmpkit.simfit.truth_doc import RobotTruth
from zmpkit.simfit.warp_batched import simulate_batches_warp

__all__ = ["CHUNK_S", "simulate_batch", "simulate_batches"]

CHUNK_S = 1.0
"""Simulated time per batch call [s]: fallen and diverged candidates drop out between calls."""
_TIME = mujoco.mjtState.mjSTATE_TIME
_INTEGRATION = mujoco.mjtState.mjSTATE_INTEGRATION


def simulate_batch(
    experiment: Experiment,
    truths: Sequence[RobotTruth],
    effects: str,
    nthread: int = 2,
    warp_device: str | None = None,
) -> list[RecordedSignals]:
    """The signals each candidate's simulator records in ``experiment``.

    Args:
        experiment: the recorded experiment to replay.
        truths: one truth object per candidate (the experiment's robot's).
        effects: effect letters switched on, e.g. ``"M,G"``.
        nthread: threads of the batch (the cores to use).
        warp_device: roll out on MuJoCo Warp on this device (``"cuda:0"``; ``"cpu"`` for
            testing; ``""`` for Warp's default) instead of the CPU batch: float32 physics,
            so close to the serial path but not bit for bit, and only models MuJoCo Warp
            supports (the M effect on).

    Returns:
        Per candidate, what :func:`~zmpkit.simfit.rollout.simulate_experiment`
        returns for it (with ``warp_device``, its float32 approximation).
    """
    if not truths:
        return []
    if warp_device is not None:
        return simulate_batches_warp([experiment], truths, effects, warp_device)[0]
    return _simulate_posed(
        experiment, truths, posed_simulations([experiment], truths, effects)[0], effects, nthread
    )


def simulate_batches(
    experiments: Sequence[Experiment],
    truths: Sequence[RobotTruth],
    effects: str,
    nthread: int = 2,
) -> list[list[RecordedSignals]]:
    """Per experiment, :func:`simulate_batch` of it: each candidate's model compiled once.

    The same signals, bit for bit; a candidate's experiments start from copies of one
    compiled model (:func:`~zmpkit.simfit.open_loop.posed_simulations`).
    """
    if not truths:
        return [[] for _ in experiments]
    posed = posed_simulations(experiments, truths, effects)
    return [
        _simulate_posed(experiment, truths, sims, effects, nthread)
        for experiment, sims in zip(experiments, posed, strict=True)
    ]


def _simulate_posed(
    experiment: Experiment,
    truths: Sequence[RobotTruth],
    sims: Sequence[Simulation],
    effects: str,
    nthread: int,
) -> list[RecordedSignals]:
    """:func:`simulate_batch` from the candidates' posed simulations."""
    schedule = open_loop_schedule(experiment, sims[0])
    out: list[RecordedSignals | None] = [None] * len(sims)
    for group in layout_groups(sims):
        rows = BatchRows(experiment, [sims[i] for i in group], schedule)
        _run(rows, [sims[i] for i in group], schedule, nthread)
        for i, j in enumerate(group):
            if rows.rerun[i]:
                out[j] = simulate_experiment(experiment, truths[j], effects)
            else:
                out[j] = rows.signals(i)
    return [s for s in out if s is not None]


def _run(
    rows: BatchRows, sims: Sequence[Simulation], schedule: OpenLoopSchedule, nthread: int
) -> None:
    """Roll every candidate out chunk by chunk, filling ``rows``."""
    n = len(sims)
    model0 = sims[0].model
    start = schedule.start_step
    batch = mujoco.batch.Batch(model0, n, nthread=nthread)
    if n > 1:
        batch.set_models([s.model for s in sims])
    for i, sim in enumerate(sims):
        mujoco.mj_getState(sim.model, sim.data, batch.state[i], _INTEGRATION)
    controls = np.stack([s.controls_of(schedule.setpoints_rad) for s in sims])
    ft_every = sims[0].ft_sample_every
    t0 = np.array([s.data.time for s in sims])
    dt = sims[0].dt
    chunk = max(1, round(CHUNK_S / dt))
    nstep = len(schedule.setpoints_rad)
    records = ("qpos", "qvel", "sensordata", "site_xpos", "site_xmat", _TIME)
    for c0 in range(0, nstep, chunk):
        alive = [i for i in range(n) if not rows.done[i]]
        if not alive:
            return
        c1 = min(nstep, c0 + chunk)
        before = batch.warning[alive, :, 1].copy()
        out = batch.rollout(c1 - c0, controls[alive, c0:c1], record=records, ids=alive)
        out["time"] = out.pop(_TIME)
        steps = start + np.arange(c0 + 1, c1 + 1)  # the step each recorded row ends
        ft_rows = np.flatnonzero(steps % ft_every == 0)
        measured = ft_readings(rows, sims, alive, out["sensordata"][:, ft_rows])
        warned = batch.warning[alive, :, 1] != before
        read_candidates(rows, alive, out, steps, ft_rows, measured, warned, t0, dt)
