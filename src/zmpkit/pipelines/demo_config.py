"""The settings of ``zmpkit demo``: the pendulum, the ZMP step, the robots, which parts run."""

from __future__ import annotations

from dataclasses import dataclass, field

from zmpkit.robots.registry import DEFAULT_BALANCE_ROBOT, DEFAULT_WALK_ROBOT, get_robot
from zmpkit.robots.robot import BalanceModel, Robot

__all__ = ["DEMO_STEP_M", "PAPER_ZETA", "DemoConfig"]

DEMO_STEP_M = 0.09  # the 9 cm ZMP disturbance of paper A, Fig. 18 [m]
PAPER_ZETA = 0.8
"""Paper A's damping ratio of the DLIPM design [-]."""


@dataclass(frozen=True)
class DemoConfig:
    """Demo settings: pendulum of mass [kg] and length [m], ZMP step [m], duration [s].

    The pendulum is the balance robot's model (paper A §4.1's by default); the balance part
    runs on ``balance_robot``, the walks and the compensation on ``walk_robot``. Every report
    is written as ``report_format`` (``html``, ``md`` or ``both``). ``video`` draws the walks
    side by side and a balance step trial (:mod:`zmpkit.analysis.walk_video`,
    :mod:`zmpkit.pipelines.balance_video`).
    """

    mass_kg: float = field(default_factory=lambda: _balance_model().mass_kg)
    length_m: float = field(default_factory=lambda: _balance_model().com_height_m)
    zmp_step_m: float = DEMO_STEP_M
    zeta: float = PAPER_ZETA
    duration_s: float = 20.0
    dt_s: float = 0.002
    balance: bool = True
    walking: bool = True
    compensation: bool = True
    balance_robot: Robot = field(default_factory=lambda: get_robot(DEFAULT_BALANCE_ROBOT))
    walk_robot: Robot = field(default_factory=lambda: get_robot(DEFAULT_WALK_ROBOT))
    report_format: str = "html"
    video: bool = True

    def __post_init__(self) -> None:
        # a registry name or robot.yaml path, from Python, is resolved once, here
        object.__setattr__(self, "balance_robot", get_robot(self.balance_robot))
        object.__setattr__(self, "walk_robot", get_robot(self.walk_robot))


def _balance_model() -> BalanceModel:
    return get_robot(DEFAULT_BALANCE_ROBOT, needs="balance").require_balance()
