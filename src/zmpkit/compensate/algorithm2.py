r"""Paper B's Algorithm 2: compensate measured ZMP deviations online, with a bias filter (Fig. 10).

Inside the walking loop, at every motion frame ``i`` (10 ms) with the measured ZMP ``p``,
the desired ZMP ``p_r`` and one offset per frame of a step, ``p_o[0..T-1]`` (``T`` frames per
step, 50 for paper B's 0.5 s steps), paper B writes::

    b = α1 b + (1 - α1)(p_r - p)                       # bias of the deviation
    p' = p_r + p_o[i mod T]                             # desired ZMP of this frame
    p_o[i mod T] = α2 p_o[i mod T] + (1 - α2) p_r - p + b   # "add difference, remove bias"

Line 7 is printed without brackets and with ``+ b``; read literally it would store
``-α2 p_r`` in the offset (tens of centimetres), contradicting its comment. zmpkit reads it as
the comment and the text say — the smoothed deviation with its bias removed:

.. math::

    p_o[i \bmod T] \leftarrow \alpha_2\, p_o[i \bmod T] + (1-\alpha_2)\,(p_r - p - b).

Online this means: each frame the preview controller advances the CoM one period with the
window ``p_r(i+j) + p_o[(i+j) mod T]``, ``j = 0..N_L`` (future frames with today's offsets),
the whole-body IK turns CoM and feet into joint targets, and the simulated robot's F-T
sensors give the next ``p``. ``i`` counts frames from the start of walking, so ``p_o[k]`` is
tied to one phase of the step; the offsets act only between the first lift-off's weight
transfer and the last touch-down.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.errors import ParameterError
from zmpkit.experiments.walk_trial import FrameReading
from zmpkit.walking.ik import IkSettings, WalkingIk
from zmpkit.walking.pattern import WalkingPattern
from zmpkit.walking.preview import PreviewController

__all__ = ["Algorithm2Offsets", "Algorithm2Parameters", "OnlineZmpCompensator"]


@dataclass(frozen=True)
class Algorithm2Parameters:
    """Gains of Algorithm 2 (paper B gives none; these are zmpkit's defaults).

    Attributes:
        bias_gain: α1 of the bias filter, per frame [-] (0.99: time constant ~1 s at 10 ms).
        smoothing_gain: α2 of the offset update, per step [-].
        axes: ZMP axes compensated (0 = x, walking direction; 1 = y) [-].
    """

    bias_gain: float = 0.99
    smoothing_gain: float = 0.8
    axes: tuple[int, ...] = (0,)

    def __post_init__(self) -> None:
        for name in ("bias_gain", "smoothing_gain"):
            value = getattr(self, name)
            if not 0.0 <= value < 1.0:
                raise ParameterError(f"Algorithm2Parameters.{name} must be in [0, 1); got {value}")
        if not self.axes or any(a not in (0, 1) for a in self.axes):
            raise ParameterError(f"Algorithm2Parameters.axes must hold 0 and/or 1; got {self.axes}")


class Algorithm2Offsets:
    """Lines 5 and 7 of Algorithm 2: the bias ``b`` and the offsets ``p_o`` of each frame of a step.

    Shared by both ways zmpkit runs the algorithm: with its own preview controller on an open
    loop (:class:`OnlineZmpCompensator`) and, as paper B's robot runs it (line 3: "ZMP/IP-
    Controller(p')"), adapting the reference of the feedback walk's observed preview control
    (:meth:`adapt`, the ``reference_adapter`` of
    :class:`~zmpkit.walking.walk_controllers.ZmpIpWalk`).

    Args:
        pattern: the planned (uncompensated) walk; its linear reference is p_r.
        parameters: α1, α2 and the axes.
    """

    def __init__(self, pattern: WalkingPattern, parameters: Algorithm2Parameters) -> None:
        self.parameters = parameters
        plan = pattern.footsteps
        dt = pattern.config.control_period_s
        self.frames_per_step = round(plan.gait.step_duration_s / dt)
        self.first_frame = round(plan.walk_start_s / dt)
        self.last_frame = round(plan.steps[-1].t_end / dt)
        self.desired = pattern.linear_zmp_reference.zmp_in_world
        n = self.desired.shape[0]
        self.offsets = np.zeros((self.frames_per_step, 2))
        """p_o: one offset per frame of a step, (x, y) [m], shape (T, 2)."""
        self.bias = np.zeros(2)
        """b: the low-passed deviation p_r - p, (x, y) [m]."""
        self.target = self.desired.copy()
        """p': the reference actually tracked at each frame [m], shape (N, 2)."""
        self.measured = np.full((n, 2), np.nan)
        """p: the measured ZMP of each frame [m], shape (N, 2) (NaN: none)."""

    def _slot(self, frame: int) -> int | None:
        if not self.first_frame <= frame <= self.last_frame:
            return None
        return (frame - self.first_frame) % self.frames_per_step

    def update(self, frame: int, zmp_in_world: NDArray[np.float64]) -> int | None:
        """Lines 5 and 7 for frame ``frame`` with its measured ZMP [m] (skipped if NaN).

        Returns:
            The slot of ``p_o`` that changed, or None (outside the walk, or no ZMP).
        """
        self.measured[frame] = zmp_in_world
        slot = self._slot(frame)
        if slot is None or not np.all(np.isfinite(zmp_in_world)):
            return None
        a1, a2 = self.parameters.bias_gain, self.parameters.smoothing_gain
        axes = list(self.parameters.axes)
        deviation = self.desired[frame, axes] - zmp_in_world[axes]
        self.bias[axes] = a1 * self.bias[axes] + (1.0 - a1) * deviation
        old = self.offsets[slot, axes]
        self.offsets[slot, axes] = a2 * old + (1.0 - a2) * (deviation - self.bias[axes])
        return slot

    def adapt(
        self,
        frame: int,
        zmp_in_world: NDArray[np.float64],
        reference_by_axis: Sequence[NDArray[np.float64]],
    ) -> None:
        """Lines 5–7 inside a feedback walk: learn from frame ``frame``, rewrite its future.

        After the update of ``p_o[s]`` (``s`` the slot of ``frame``), every frame ``k ≥
        frame`` of the walk with that slot gets ``p'_k = p_{r,k} + p_o[s]`` in the controller's
        reference, so that the preview window always reads today's offsets (line 6); the
        other frames keep theirs. O(walk frames / T) writes per frame, no allocation per call
        beyond numpy's slice arithmetic.

        Args:
            frame: the frame the measurement belongs to [-].
            zmp_in_world: the measured ZMP (x, y) [m]; NaN: nothing is learnt.
            reference_by_axis: the controller's reference, one writable array per axis (x,
                y) [m], indexed by frame.
        """
        slot = self.update(frame, zmp_in_world)
        if slot is not None:
            stop, step = self.last_frame + 1, self.frames_per_step
            for axis in self.parameters.axes:
                reference_by_axis[axis][frame:stop:step] = (
                    self.desired[frame:stop:step, axis] + self.offsets[slot, axis]
                )
        if frame < self.target.shape[0]:
            self.target[frame, 0] = reference_by_axis[0][frame]
            self.target[frame, 1] = reference_by_axis[1][frame]

    def reference_window(self, frame: int, length: int) -> NDArray[np.float64]:
        """Line 6 for frames ``frame .. frame + length - 1``: p_r + p_o [m], shape (length, 2)."""
        n = self.desired.shape[0]
        idx = np.minimum(np.arange(frame, frame + length), n - 1)
        window = self.desired[idx].copy()
        for j, k in enumerate(idx):
            slot = self._slot(int(k))
            if slot is not None:
                window[j] += self.offsets[slot]
        return window


class _OnlineTargets:
    """What the IK reads of a pattern, with the CoM written frame by frame."""

    def __init__(self, pattern: WalkingPattern) -> None:
        self.feet = pattern.feet
        self.com_position_in_world = pattern.com_position_in_world.copy()


class OnlineZmpCompensator(Algorithm2Offsets):
    """Algorithm 2 as a ``frame_hook`` of :func:`~zmpkit.experiments.walk_trial.simulate_walk`.

    Its own preview controller plans the CoM on the compensated reference with no state
    feedback (the open-loop walk's); the whole-body IK turns it into joint targets.

    Args:
        pattern: the planned (uncompensated) walk; its linear reference is p_r.
        model: the IK's rigid model.
        parameters: α1, α2 and the axes.
        ik_settings: the IK settings the planned trajectory was solved with.
    """

    def __init__(self, pattern: WalkingPattern, model: mujoco.MjModel,
                 parameters: Algorithm2Parameters, ik_settings: IkSettings) -> None:  # fmt: skip
        super().__init__(pattern, parameters)
        dt = pattern.config.control_period_s
        self.controller = PreviewController(pattern.gains, tuple(self.desired[0]))
        self.window = self.controller.window_length
        self.targets = _OnlineTargets(pattern)
        self.ik = WalkingIk(model, ik_settings)
        self.ik.set_targets(self.targets, 0)
        self.ik.solve(ik_settings.max_iterations * 10, dt)
        self.dt = dt

    def __call__(self, frame: int, reading: FrameReading) -> NDArray[np.float64]:
        """Joint targets of ``frame`` [rad] from the reading of ``frame - 1``."""
        zmp = reading.zmp_in_world()
        self.update(reading.frame, zmp)
        window = self.reference_window(frame - 1, self.window)
        self.target[frame - 1] = window[0]
        self.controller.step(window[:, 0], window[:, 1])
        self.targets.com_position_in_world[frame, :2] = self.controller.state_in_world[:, 0]
        self.ik.set_targets(self.targets, frame)
        self.ik.solve(self.ik.settings.max_iterations, self.dt)
        return self.ik.configuration.q[self.ik.qadr].copy()
