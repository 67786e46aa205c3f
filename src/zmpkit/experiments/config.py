"""Configuration of a step / push experiment sweep (paper A §4.1, Fig. 12–14).

A sweep runs one trial per ZMP target: the robot stands in double support, settles, records a
quiet start-up window (for the ZMP offset, as paper A's code does at start-up), then at
``t_step`` gets the LIPM lean for the target — optionally with a push at the same time —
and holds it while everything is recorded. A target of 0 with a push is a pure push trial.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import asdict, dataclass, fields
from typing import Any

from zmpkit._validate import finite, in_range, positive
from zmpkit.errors import ParameterError
from zmpkit.experiments.ft_faults import FtFaults
from zmpkit.robots.robot import Robot
from zmpkit.signals import PLANES
from zmpkit.sim.effect_set import EffectSet

__all__ = [
    "DEFAULT_TARGETS_M",
    "MAX_HOLD_S",
    "MAX_PUSH_DURATION_S",
    "MAX_PUSH_FORCE_N",
    "PUSH_POINTS",
    "PushConfig",
    "StepExperimentConfig",
    "parse_targets",
    "trial_file_name",
]

PUSH_POINTS = ("com", "trunk")
"""Where a push acts: the whole-body CoM, or the trunk body's CoM."""
DEFAULT_TARGETS_M: tuple[float, ...] = tuple(round(0.01 * k, 10) for k in range(11))
"""Default ZMP targets, 0.00 … 0.10 m in 0.01 m steps (paper A Fig. 14–16) [m]."""
MAX_HOLD_S = 600.0
"""Longest recorded time after the step [s]: ten minutes, 40 times the settling of paper A."""
MAX_PUSH_FORCE_N = 2000.0
"""Largest |push force| [N]: three times the heaviest built-in robot's weight; more only throws."""
MAX_PUSH_DURATION_S = 10.0
"""Longest push [s]; a longer one is a lean, not a push."""
_TARGET_DECIMALS = 9
_RANGE = re.compile(r"^\s*([^:]+):([^:]+):([^:]+)\s*$")


@dataclass(frozen=True)
class PushConfig:
    """A push applied at ``t_step`` in the plane of the experiment.

    Attributes:
        force_n: force along +x (sagittal) or +y (frontal); negative pushes back [N], at
            most :data:`MAX_PUSH_FORCE_N` in size.
        duration_s: how long it acts [s], in (0, :data:`MAX_PUSH_DURATION_S`].
        point: ``"com"`` (the whole-body CoM) or ``"trunk"`` (the trunk body's CoM).
    """

    force_n: float
    duration_s: float
    point: str = "com"

    def __post_init__(self) -> None:
        force = in_range("push force_n", self.force_n, -MAX_PUSH_FORCE_N, MAX_PUSH_FORCE_N, "N")
        duration = positive("push duration_s", self.duration_s, "s")
        if duration > MAX_PUSH_DURATION_S:
            raise ParameterError(
                f"push duration_s must lie in (0, {MAX_PUSH_DURATION_S:g}] s, got {duration:g} s"
            )
        object.__setattr__(self, "force_n", force)
        object.__setattr__(self, "duration_s", duration)
        if self.point not in PUSH_POINTS:
            raise ParameterError(
                f"push point must be one of {', '.join(PUSH_POINTS)}; got {self.point!r}"
            )


@dataclass(frozen=True)
class StepExperimentConfig:
    """A sweep of ZMP-step (and push) trials.

    Attributes:
        robot: the robot; it needs a balance model (the dataset records its
            :attr:`~zmpkit.robots.robot.Robot.source`).
        targets_m: ZMP targets, one trial each, |target| < the lean length [m].
        plane: ``"sagittal"`` (ZMP x) or ``"frontal"`` (ZMP y).
        effects: ``"all"``, ``"none"`` or letters such as ``"M,G,S"`` (canonical form kept).
        seed: seed of the sensor noise; each trial derives its own stream from it.
        settle_s: time the robot stands before recording starts [s]; with every effect on
            the drives' integrators need about 3 s to settle.
        startup_window_s: recorded quiet standing before the step, used for the ZMP offset [s].
        hold_s: recorded time after the step [s], in (0, :data:`MAX_HOLD_S`]; with
            ``max_hold_s``, the shortest hold.
        max_hold_s: if set, the hold is extended, a second at a time, until the measured ZMP
            has settled (creep included, :mod:`zmpkit.experiments.hold`), up to this [s], at
            most :data:`MAX_HOLD_S`.
        push: optional push at ``t_step``.
        truth: path of a truth file replacing the shipped one, or ``None``.
        faults: F-T faults injected into what a feedback controller reads, kinds from
            :data:`~zmpkit.experiments.ft_faults.FAULT_KINDS` (:mod:`.ft_faults`); the
            recorded data stay clean.
    """

    robot: Robot
    targets_m: tuple[float, ...] = DEFAULT_TARGETS_M
    plane: str = "sagittal"
    effects: str = "all"
    seed: int = 0
    settle_s: float = 3.0
    startup_window_s: float = 0.5
    hold_s: float = 15.0
    max_hold_s: float | None = None
    push: PushConfig | None = None
    truth: str | None = None
    faults: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        self.robot.require_balance()
        object.__setattr__(self, "faults", tuple(self.faults))
        if self.faults:
            FtFaults(self.faults)  # checks the kinds
        if self.plane not in PLANES:
            raise ParameterError(f"plane must be one of {', '.join(PLANES)}; got {self.plane!r}")
        object.__setattr__(self, "effects", EffectSet.parse(self.effects).letters)
        object.__setattr__(self, "targets_m", _clean_targets(self.targets_m))
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ParameterError(f"seed must be an integer >= 0, got {self.seed!r}")
        positive("settle_s", self.settle_s, "s")
        positive("startup_window_s", self.startup_window_s, "s")
        if not 0.0 < positive("hold_s", self.hold_s, "s") <= MAX_HOLD_S:
            raise ParameterError(f"hold_s must lie in (0, {MAX_HOLD_S:g}] s, got {self.hold_s:g} s")
        if self.max_hold_s is not None and not (
            self.hold_s <= positive("max_hold_s", self.max_hold_s, "s") <= MAX_HOLD_S
        ):
            raise ParameterError(
                f"max_hold_s must lie in [hold_s = {self.hold_s:g}, {MAX_HOLD_S:g}] s, "
                f"got {self.max_hold_s:g} s"
            )
        if self.truth is not None:
            object.__setattr__(self, "truth", str(self.truth))

    @property
    def t_step_s(self) -> float:
        """Time of the step after the start of the simulation [s]."""
        return self.settle_s + self.startup_window_s

    @property
    def duration_s(self) -> float:
        """Simulated length of one trial with the shortest hold [s]."""
        return self.t_step_s + self.hold_s

    def settings(self) -> dict[str, Any]:
        """Everything that decides a trial's data except its target, as JSON-ready values.

        The robot is its :attr:`~zmpkit.robots.robot.Robot.source`.
        """
        out = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "targets_m"}
        out["robot"] = self.robot.source
        if self.push is not None:
            out["push"] = asdict(self.push)
        if not self.faults:
            out.pop("faults")  # as before faults existed: older datasets resume
        return out


def _clean_targets(values: Iterable[float]) -> tuple[float, ...]:
    try:
        targets = tuple(round(finite("target", float(v)), _TARGET_DECIMALS) for v in values)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"targets must be a sequence of numbers [m]: {exc}") from None
    if not targets:
        raise ParameterError("targets must hold at least one ZMP target [m], got none")
    if len(set(targets)) != len(targets):
        raise ParameterError(f"targets must be distinct, got {list(targets)}")
    return targets


def trial_file_name(plane: str, target_m: float) -> str:
    """``trial_<plane>_<target in mm>.csv``, e.g. ``trial_sagittal_0030.csv``; ``m`` for minus.

    Sub-millimetre targets get the micrometres after a ``p``: ``trial_sagittal_0012p500.csv``.
    """
    micro = round(target_m * 1e6)
    sign = "m" if micro < 0 else ""
    mm, rest = divmod(abs(micro), 1000)
    frac = f"p{rest:03d}" if rest else ""
    return f"trial_{plane}_{sign}{mm:04d}{frac}.csv"


def parse_targets(text: str, option: str = "--targets") -> tuple[float, ...]:
    """Parse ``START:STOP:STEP`` (stop included) or a comma list such as ``0,0.02,0.05`` [m].

    Raises:
        ParameterError: naming ``option`` and the expected form.
    """
    form = (
        f"{option} expects START:STOP:STEP in m (stop included, e.g. 0:0.10:0.01) or a comma list"
    )
    try:
        match = _RANGE.match(text)
        if match:
            start, stop, step = (float(g) for g in match.groups())
            if not all(map(math.isfinite, (start, stop, step))) or step <= 0 or stop < start:
                raise ValueError
            count = math.floor((stop - start) / step + 1e-9) + 1
            return tuple(round(start + k * step, _TARGET_DECIMALS) for k in range(count))
        values = tuple(float(v) for v in text.split(","))
        if not all(map(math.isfinite, values)):
            raise ValueError
        return values
    except ValueError:
        raise ParameterError(f"{form} (e.g. 0,0.02,0.05); got {text!r}") from None
