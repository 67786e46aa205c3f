"""What each candidate of a batch records, read from the batch's rows.

Read as the serial path reads its simulation: F-T readings held between samples, encoders,
IMU, a walk's fall. Rows hold every column, or only those the cost reads
(:class:`~zmpkit.simfit.cost_columns.CostColumns`; the encoders then summed elsewhere).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from zmpkit.experiments.walk_trial import FALL_TILT_RAD, FALL_TORSO_HEIGHT_FRACTION
from zmpkit.sensors.imu import quaternion_pitch_roll, tilt_from_quaternions
from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sim.description import FootSensor
from zmpkit.sim.posed import StartedSimulation
from zmpkit.simfit.cost_columns import HEIGHT_QPOS, CostColumns
from zmpkit.simfit.experiments import Experiment, StepExperiment, WalkExperiment
from zmpkit.simfit.open_loop import OpenLoopSchedule
from zmpkit.simfit.recorded import RecordedSignals
from zmpkit.simfit.rollout import empty_signals, step_readings, step_signals, walk_forces

__all__ = ["BatchRows"]


class BatchRows:
    """What each candidate records, filled chunk by chunk: a list of row blocks each.

    Args:
        experiment: the experiment replayed.
        sims: the candidates' posed simulations.
        schedule: the experiment's open-loop schedule.
        columns: the rows hold only these columns (no encoders: :meth:`signals` is then
            unavailable; :meth:`cost_readings` and :attr:`posed_square` serve the cost), or
            None for every column.
    """

    def __init__(
        self,
        experiment: Experiment,
        sims: Sequence[StartedSimulation],
        schedule: OpenLoopSchedule,
        columns: CostColumns | None = None,
    ) -> None:
        self.experiment, self.sims, self.schedule = experiment, sims, schedule
        self.columns = columns
        self.walk = isinstance(experiment, WalkExperiment)
        sim = sims[0]
        self.feet = tuple(f.foot for f in sim.robot.feet)
        if columns is None:
            self.ft_sites = [sim.model.site(f.site).id for f in sim.robot.feet]
            quat = sim.sensor_slice(sim.robot.imu.orientation)
            self.quat = np.arange(quat.start, quat.stop)
            self._ft_index = np.stack([_ft_columns(sim, f) for f in sim.robot.feet])
            self._height = HEIGHT_QPOS
        else:
            self.ft_sites = list(range(len(columns.sites)))
            self.quat = columns.quat_positions
            self._ft_index = columns.ft_positions
            self._height = columns.qpos.index(HEIGHT_QPOS)
        self.sensors = [s.robot.effects.sensors for s in sims]
        n = len(sims)
        self.done = [False] * n
        self.rerun = [False] * n
        self.diverged = [False] * n
        self.posed_square = [0.0] * n
        """Per candidate, the joint term's sum over the posed row [rad²] (with ``columns``)."""
        self.blocks: list[list[dict[str, NDArray[np.float64]]]] = [[] for _ in range(n)]
        self.ft_now = [np.array([s.ft_channel(f).output for f in self.feet]) for s in sims]
        self.fall_height_m = [FALL_TORSO_HEIGHT_FRACTION * float(s.data.qpos[2]) for s in sims]
        """Each candidate's fall height, from its posed torso (the serial path's rule) [m]."""
        if schedule.record_steps[0] == schedule.start_step:
            for i in range(n):
                self.read_posed(i)

    def ft_true(self, sensordata: NDArray[np.float64]) -> NDArray[np.float64]:
        """The true wrenches of rows ``(..., columns)``, ``(..., feet, 6)`` [N, N·m].

        C-ordered, as the serial path's: numpy's products sum in an order that follows the
        memory layout, and the batch must give the serial path's numbers bit for bit.
        """
        return np.ascontiguousarray(-sensordata[..., self._ft_index])

    def read_posed(self, i: int) -> None:
        """The row of the posed state (a walk's frame 0; the serial path checks no fall)."""
        sim = self.sims[i]
        data, cols = sim.data, self.columns
        block = {"time": np.array([data.time])}
        if cols is None:
            block["qpos"] = data.qpos[None].copy()
            block["sensordata"] = data.sensordata[None].copy()
            block["site_xpos"] = data.site_xpos[None, self.ft_sites].copy()
            block["site_xmat"] = data.site_xmat[None, self.ft_sites].copy()
        else:
            block["qpos"] = data.qpos[None, list(cols.qpos)]
            block["sensordata"] = data.sensordata[None, list(cols.sensordata)]
            block["site_xpos"] = data.site_xpos[None, list(cols.sites)]
            block["site_xmat"] = data.site_xmat[None, list(cols.sites)]
            signals = self.experiment.signals
            keep = [sim.joint_names.index(j) for j in signals.joint_names]
            miss = sim.encoders_of(data.qpos)[keep] - signals.q_meas_rad[0]
            self.posed_square[i] = float(np.sum(np.square(miss)))
        block["ft"] = self._ft(i, block["sensordata"], self.ft_now[i][None])
        self.blocks[i].append(block)

    def _ft(
        self, i: int, sensordata: NDArray[np.float64], sampled: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """F-T readings (rows, feet, 6): the last samples (S on) or the true wrench."""
        if self.sensors[i]:
            return sampled
        return self.ft_true(sensordata)

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
                rows["qpos"][wanted, self._height],
                rows["sensordata"][wanted][:, self.quat],
                self.fall_height_m[i],
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

    def _joined(self, i: int) -> dict[str, NDArray[np.float64]] | None:
        """The candidate's rows in one block each, or None (none, or a diverged walk)."""
        blocks = self.blocks[i]
        if not blocks or (self.walk and self.diverged[i]):
            return None
        rows = {k: np.concatenate([b[k] for b in blocks]) for k in blocks[0]}
        return rows if len(rows["time"]) else None

    def signals(self, i: int) -> RecordedSignals:
        """The candidate's recorded signals (rows with every column)."""
        if self.columns is not None:
            raise ValueError("rows of chosen columns hold no encoders; use cost_readings")
        signals = self.experiment.signals
        rows = self._joined(i)
        if rows is None:
            return empty_signals(signals)
        n = len(rows["time"])
        sim = self.sims[i]
        encoders = sim.encoders_of(rows["qpos"])
        quats = rows["sensordata"][:, self.quat]
        if isinstance(self.experiment, StepExperiment):  # not self.walk
            right, left = (rows["ft"][:, self.feet.index(f)] for f in ("right", "left"))
            data = np.concatenate([right, left, encoders, quats], axis=1)
            return step_signals(self.experiment, data, n)
        time, zmp, force, tilt = self._walk_readings(rows)
        keep = [sim.joint_names.index(j) for j in signals.joint_names]
        return RecordedSignals(
            time,
            signals.joint_names,
            self.schedule.q_cmd_rad[:n],
            encoders[:, keep],
            zmp,
            tilt,
            force,
        )

    def cost_readings(
        self, i: int
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """The candidate's ZMP [m], feet's vertical forces [N] and trunk tilt [rad].

        Shapes ``(rows, 2)`` (x, y), ``(rows, 2)`` (right, left) and ``(rows,)``. As in
        :meth:`signals`: no rows for a diverged walk, none for a step trial with fewer
        than two.
        """
        rows = self._joined(i)
        n = 0 if rows is None else len(rows["time"])
        if rows is None or (not self.walk and n < 2):
            return np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0)
        quats = rows["sensordata"][:, self.quat]
        if isinstance(self.experiment, StepExperiment):
            right, left = (rows["ft"][:, self.feet.index(f)] for f in ("right", "left"))
            return step_readings(self.experiment, right, left, quats)
        _, zmp, force, tilt = self._walk_readings(rows)
        return zmp, force, tilt

    def _walk_readings(
        self, rows: dict[str, NDArray[np.float64]]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray]:
        """A walk's row times [s], ZMP [m], feet's vertical forces [N], trunk pitch [rad]."""
        force, moment = wrench_in_world(rows["site_xmat"], rows["ft"])
        zmp = zmp_in_world(
            force, moment, rows["site_xpos"], self.sims[0].robot.contact_force_threshold_n
        )
        quats = rows["sensordata"][:, self.quat]
        tilt = tilt_from_quaternions(quats, "sagittal")
        return rows["time"], zmp, walk_forces(self.feet, force), tilt


def _ft_columns(sim: StartedSimulation, foot: FootSensor) -> NDArray[np.int64]:
    """The sensordata columns of a foot's F-T force then torque (``ft_true_of``'s order)."""
    force = sim.sensor_slice(foot.force_sensor)
    torque = sim.sensor_slice(foot.torque_sensor)
    return np.r_[force.start : force.stop, torque.start : torque.stop]


def _first_fall(
    height: NDArray[np.float64], quat: NDArray[np.float64], fall_height_m: float
) -> int | None:
    """The first row where the serial path's fall rule fires, or None.

    ``height``: the torso height of each row [m]; ``fall_height_m``: the height below which
    it has fallen [m].

    Screened with numpy, decided with the serial path's own scalar rule (so a tilt within
    rounding of the limit is judged exactly as there).
    """
    w, x, y, z = quat.T
    pitch = np.arcsin(np.clip(2.0 * (w * y - z * x), -1.0, 1.0))
    roll = np.arctan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    margin = 1e-9
    near = np.maximum(np.abs(pitch), np.abs(roll)) > FALL_TILT_RAD - margin
    near |= height < fall_height_m + margin
    for r in np.flatnonzero(near):
        p, q = quaternion_pitch_roll(quat[r])
        if max(abs(p), abs(q)) > FALL_TILT_RAD or float(height[r]) < fall_height_m:
            return int(r)
    return None
