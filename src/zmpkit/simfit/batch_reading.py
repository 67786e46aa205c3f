"""Reading a batch's recorded rows into each candidate's signals, as the serial path would.

Shared by the CPU batch (:mod:`~zmpkit.simfit.batched`) and the MuJoCo Warp batch
(:mod:`~zmpkit.simfit.warp_batched`): which candidates can share one batch (their models
give MjData the same layout), the F-T readings at the sample steps (the same noise as the
serial path, :func:`~zmpkit.sim.sensing.sample_series`), and the judgement of each
candidate's rows — a MuJoCo warning other than bad acceleration sends it back to the serial
path; a time that stops advancing or a joint speed beyond
:data:`~zmpkit.sim.world.DIVERGED_SPEED_RAD_S` at an F-T sample ends its signals.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.sim.posed import StartedSimulation
from zmpkit.sim.sensing import sample_series
from zmpkit.sim.world import DIVERGED_SPEED_RAD_S
from zmpkit.simfit.batch_rows import BatchRows

__all__ = ["ft_readings", "layout_groups", "read_candidates"]

_BADQACC = int(mujoco.mjtWarning.mjWARN_BADQACC)
_LAYOUT_SIZES = (
    "nq", "nv", "na", "nu", "nbody", "njnt", "ngeom", "nsite", "ntendon", "neq",
    "nsensordata", "nwrap", "nmocap",
)  # fmt: skip


def layout_groups(sims: Sequence[StartedSimulation]) -> list[list[int]]:
    """Candidates whose models give MjData the same layout (one batch each)."""
    groups: dict[tuple[int, ...], list[int]] = {}
    for i, sim in enumerate(sims):
        key = tuple(getattr(sim.model, size) for size in _LAYOUT_SIZES)
        groups.setdefault(key, []).append(i)
    return list(groups.values())


def read_candidates(
    rows: BatchRows,
    alive: list[int],
    out: dict,
    steps: NDArray[np.int64],
    ft_rows: NDArray[np.int64],
    measured: NDArray[np.float64],
    warned: NDArray[np.bool_],
    t0: NDArray[np.float64],
    dt: float,
    valid: NDArray[np.int64] | None = None,
) -> None:
    """Judge each alive candidate's rows of a chunk (divergence) and keep the wanted ones.

    Args:
        rows: what each candidate records; filled, and its done/rerun/diverged flags set.
        alive: the candidates (indices into ``rows``) simulated in this chunk.
        out: the chunk's records, ``(alive, rows, ...)`` per item (``qvel`` optional when
            ``valid`` covers the speeds).
        steps: the step each recorded row ends (every step, or, on MuJoCo Warp, those the
            signals read).
        ft_rows: the rows that are F-T sample steps.
        measured: the F-T readings at those samples, (alive, samples, feet, 6).
        warned: per alive candidate, which MuJoCo warnings rose in the chunk.
        t0: each candidate's time at the start [s].
        dt: the physics time step [s].
        valid: rows each candidate's engine vouches for (MuJoCo Warp), or None.
    """
    start = rows.schedule.start_step
    for a, i in enumerate(alive):
        if np.delete(warned[a], _BADQACC).any():
            rows.rerun[i] = rows.done[i] = True
            continue
        expected = t0[i] + (steps - start) * dt
        bad = np.flatnonzero(np.abs(out["time"][a, :, 0] - expected) > 0.5 * dt)
        fast = ft_rows[:0]  # MuJoCo Warp checks the speeds itself (``valid``)
        if "qvel" in out:
            speed = out["qvel"][a, ft_rows]
            fast = ft_rows[~np.all(np.abs(speed) <= DIVERGED_SPEED_RAD_S, axis=1)]
        limit = min(bad[0] if len(bad) else len(steps), fast[0] if len(fast) else len(steps))
        if valid is not None:
            limit = min(limit, int(valid[a]))
        rows.read_chunk(i, {k: v[a] for k, v in out.items()}, steps, ft_rows, measured[a], limit)
        flagged = warned[a, _BADQACC] and limit == len(steps)
        if (limit < len(steps) or flagged) and not rows.done[i]:
            rows.diverged[i] = rows.done[i] = True


def ft_readings(
    rows: BatchRows,
    sims: Sequence[StartedSimulation],
    alive: list[int],
    sensordata: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The F-T readings at the chunk's sample steps, (alive, samples, feet, 6).

    Args:
        rows: what each candidate records (its feet, and which have the sensor effect on).
        sims: every candidate's simulation (its F-T channels).
        alive: the candidates (indices into ``sims``) simulated in this chunk.
        sensordata: MuJoCo's sensor rows at those steps, (alive, samples, nsensordata).
    """
    wrenches = rows.ft_true(sensordata)
    noisy = [a for a, i in enumerate(alive) if rows.sensors[i]]
    if not noisy:
        return wrenches
    out = wrenches.copy()
    # Every foot's channels in one series, foot by foot as the channels were drawn before.
    channels = [sims[alive[a]].ft_channel(f) for f in rows.feet for a in noisy]
    nfeet, nnoisy, nsample = len(rows.feet), len(noisy), wrenches.shape[1]
    feet_first = np.moveaxis(wrenches[noisy], 2, 0).reshape(nfeet * nnoisy, nsample, 6)
    with np.errstate(invalid="ignore", over="ignore"):
        sampled = sample_series(channels, feet_first)
    out[noisy] = np.moveaxis(sampled.reshape(nfeet, nnoisy, nsample, 6), 0, 2)
    return out
