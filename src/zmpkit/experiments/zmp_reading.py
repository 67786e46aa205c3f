r"""What a ZMP feedback controller reads in a trial: the gated, offset-free measured ZMP.

Each control period the reader takes the latest sample of both ankle F-T sensors (what the
robot's sensors report, never the simulator's state), passes it through the injected faults
(:class:`~zmpkit.experiments.ft_faults.FtFaults`, if any) and the plausibility gate
(:class:`~zmpkit.sensors.plausibility.PlausibilityGate`), and removes the start-up offset,
the mean ZMP over the quiet standing before the step (as paper A's code does):

.. math:: x_{meas,k} = p_k - \bar p_{startup}

A dropped or rejected sample reads None, which the controller takes as a missing sample.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Protocol

from zmpkit.experiments.ft_faults import FtFaults
from zmpkit.sensors import DoubleSupportZmp, SensorMount
from zmpkit.sensors.plausibility import PlausibilityGate, PlausibilityLimits
from zmpkit.signals import PLANES

__all__ = ["FtSource", "ZmpReader"]


class FtSource(Protocol):
    """Where the reader takes F-T samples from (a simulation, a robot's driver)."""

    def ft(self, foot: str) -> Iterable[float]:
        """The latest wrench of ``foot``'s sensor, six numbers [N, N·m]."""
        ...


class ZmpReader:
    """The measured ZMP of one plane for a feedback controller (module docstring).

    Args:
        source: gives the latest F-T samples (``ft("right")``, ``ft("left")``).
        plane: ``"sagittal"`` or ``"frontal"``.
        mounts: the feet's F-T sensor mounts, ``{"right": ..., "left": ...}``.
        contact_threshold_n: a foot is in contact above this world F_z [N] (the robot's:
            :attr:`~zmpkit.robots.robot.Robot.contact_force_threshold_n`).
        faults: faults injected into the readings after the step; None: none.
        limits: what the plausibility gate accepts; None: its defaults.
    """

    def __init__(
        self,
        source: FtSource,
        plane: str,
        mounts: Mapping[str, SensorMount],
        contact_threshold_n: float,
        faults: FtFaults | None = None,
        limits: PlausibilityLimits | None = None,
    ) -> None:
        self._source = source
        self._faults = faults
        zmp = DoubleSupportZmp(mounts["right"], mounts["left"], contact_threshold_n)
        self.gate = PlausibilityGate(zmp, PLANES.index(plane), limits)
        self._sum, self._count = 0.0, 0
        self._offset: float | None = None

    def observe_startup(self) -> None:
        """Take one sample of the quiet standing before the step into the offset."""
        value = self.gate(*self._sample())
        if value is not None:
            self._sum += value
            self._count += 1

    def read(self, time_since_step_s: float) -> float | None:
        """The measured ZMP, offset removed [m], or None (dropped or rejected sample)."""
        if self._offset is None:
            self._offset = self._sum / self._count if self._count else 0.0
        right, left = self._sample()
        if self._faults is not None and not self._faults.apply(time_since_step_s, right):
            return None
        value = self.gate(right, left)
        return None if value is None else value - self._offset

    def _sample(self) -> tuple[list[float], list[float]]:
        right, left = self._source.ft("right"), self._source.ft("left")
        return list(map(float, right)), list(map(float, left))
