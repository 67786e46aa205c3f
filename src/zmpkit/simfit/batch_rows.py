"""What each candidate of a batch records, read from the batch's rows.

Read as the serial path reads its simulation: F-T readings held between samples, encoders,
IMU, a walk's fall.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.walk_trial import FALL_TILT_RAD, FALL_TORSO_HEIGHT_FRACTION
from zmpkit.sensors.imu import quaternion_pitch_roll, tilt_from_quaternions
from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sim.world import Simulation
from zmpkit.simfit.experiments import Experiment, StepExperiment, WalkExperiment
from zmpkit.simfit.open_loop import OpenLoopSchedule
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import empty_signals, step_signals

__all__ = ["BatchRows"]


class BatchRows:
    """What each candidate records, filled chunk by chunk: a list of row blocks each."""

    def __init__(
        self, experiment: Experiment, sims: Sequence[Simulation], schedule: OpenLoopSchedule
    ) -> None:
        self.experiment, self.sims, self.schedule = experiment, sims, schedule
        self.walk = isinstance(experiment, WalkExperiment)
        sim = sims[0]
        self.feet = tuple(f.foot for f in sim.robot.feet)
        self.ft_sites = [sim.model.site(f.site).id for f in sim.robot.feet]
        self.quat = sim.sensor_slice(sim.robot.imu.orientation)
        self.sensors = [s.robot.effects.sensors for s in sims]
        n = len(sims)
        self.done = [False] * n
        self.rerun = [False] * n
        self.diverged = [False] * n
        self.blocks: list[list[dict[str, NDArray[np.float64]]]] = [[] for _ in range(n)]
        self.ft_now = [np.array([s.ft_channel(f).output for f in self.feet]) for s in sims]
        self.fall_height_m = [FALL_TORSO_HEIGHT_FRACTION * float(s.data.qpos[2]) for s in sims]
        """Each candidate's fall height, from its posed torso (the serial path's rule) [m]."""
        if schedule.record_steps[0] == schedule.start_step:
            for i in range(n):
                self.read_posed(i)

    def read_posed(self, i: int) -> None:
        """The row of the posed state (a walk's frame 0; the serial path checks no fall)."""
        data = self.sims[i].data
        block = {
            "qpos": data.qpos[None].copy(),
            "sensordata": data.sensordata[None].copy(),
            "time": np.array([data.time]),
            "site_xpos": data.site_xpos[None, self.ft_sites].copy(),
            "site_xmat": data.site_xmat[None, self.ft_sites].copy(),
        }
        block["ft"] = self._ft(i, block["sensordata"], self.ft_now[i][None])
        self.blocks[i].append(block)

    def _ft(
        self, i: int, sensordata: NDArray[np.float64], sampled: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """F-T readings (rows, feet, 6): the last samples (S on) or the true wrench."""
        if self.sensors[i]:
            return sampled
        sim = self.sims[i]
        return np.stack([sim.ft_true_of(f, sensordata) for f in self.feet], axis=1)

    def read_chunk(
        self,
        i: int,
        rows: dict[str, NDArray[np.float64]],
        steps: NDArray[np.int64],
        ft_rows: NDArray[np.int64],
        sampled: NDArray[np.float64],
        limit: int,
    ) -> None:
        """Keep candidate ``i``'s rows among a chunk's first ``limit`` steps.

        Args:
            i: the candidate's index in the batch.
            rows: the chunk's records of this candidate, one row per step.
            steps: the step each row ends.
            ft_rows: the rows that are F-T sample steps.
            sampled: the F-T readings of those samples, (len(ft_rows), feet, 6).
            limit: rows from here on are past a divergence.
        """
        wanted = np.flatnonzero(np.isin(steps[:limit], self.schedule.record_steps))
        if self.walk:
            fall = _first_fall(
                rows["qpos"][wanted], rows["sensordata"][wanted, self.quat], self.fall_height_m[i]
            )
            if fall is not None:
                wanted = wanted[: fall + 1]
                self.done[i] = True
        last = np.searchsorted(ft_rows, wanted, side="right") - 1
        held = np.concatenate([self.ft_now[i][None], sampled])[last + 1]
        block = {
            "qpos": rows["qpos"][wanted],
            "sensordata": rows["sensordata"][wanted],
            "time": rows["time"][wanted, 0],
            "site_xpos": rows["site_xpos"][wanted][:, self.ft_sites],
            "site_xmat": rows["site_xmat"][wanted][:, self.ft_sites],
        }
        block["ft"] = self._ft(i, block["sensordata"], held)
        self.blocks[i].append(block)
        taken = np.searchsorted(ft_rows, limit) - 1
        if taken >= 0:
            self.ft_now[i] = sampled[taken]

    def signals(self, i: int) -> RecordedSignals:
        """The candidate's recorded signals."""
        signals, blocks = self.experiment.signals, self.blocks[i]
        if not blocks or (self.walk and self.diverged[i]):
            return empty_signals(signals)
        rows = {k: np.concatenate([b[k] for b in blocks]) for k in blocks[0]}
        n = len(rows["time"])
        if n == 0:
            return empty_signals(signals)
        sim = self.sims[i]
        encoders = sim.encoders_of(rows["qpos"])
        quats = rows["sensordata"][:, self.quat]
        if isinstance(self.experiment, StepExperiment):  # not self.walk
            right, left = (rows["ft"][:, self.feet.index(f)] for f in ("right", "left"))
            data = np.concatenate([right, left, encoders, quats], axis=1)
            return step_signals(self.experiment, data, n)
        force, moment = wrench_in_world(rows["site_xmat"], rows["ft"])
        keep = [sim.joint_names.index(j) for j in signals.joint_names]
        return RecordedSignals(
            rows["time"],
            signals.joint_names,
            self.schedule.q_cmd_rad[:n],
            encoders[:, keep],
            zmp_in_world(force, moment, rows["site_xpos"], sim.robot.contact_force_threshold_n),
            tilt_from_quaternions(quats, "sagittal"),
        )


def _first_fall(
    qpos: NDArray[np.float64], quat: NDArray[np.float64], fall_height_m: float
) -> int | None:
    """The first row where the serial path's fall rule fires, or None.

    ``fall_height_m``: the torso height below which it has fallen [m].

    Screened with numpy, decided with the serial path's own scalar rule (so a tilt within
    rounding of the limit is judged exactly as there).
    """
    w, x, y, z = quat.T
    pitch = np.arcsin(np.clip(2.0 * (w * y - z * x), -1.0, 1.0))
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    margin = 1e-9
    near = np.maximum(np.abs(pitch), np.abs(roll)) > FALL_TILT_RAD - margin
    near |= qpos[:, 2] < fall_height_m + margin
    for r in np.flatnonzero(near):
        p, q = quaternion_pitch_roll(quat[r])
        if max(abs(p), abs(q)) > FALL_TILT_RAD or float(qpos[r, 2]) < fall_height_m:
            return int(r)
    return None
