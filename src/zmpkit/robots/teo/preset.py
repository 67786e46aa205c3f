"""The virtual TEO as a registry entry: :data:`TEO`, a :class:`~zmpkit.robots.robot.Robot`.

Balance: paper A §4.1's pendulum (62.6 kg, CoM 0.893 m), the soles' double-support extent,
and the ankle-strategy lean's joints (sagittal: ankle pitch ``*_ankle_frontal``; frontal:
ankle roll ``*_ankle_sagittal`` closed through the hip roll ``*_hip_sagittal``). TEO does not
walk in zmpkit (no walking defaults).
"""

from __future__ import annotations

from pathlib import Path

from zmpkit.robots.robot import BalanceModel, FitSpec, Robot, TruthSpec
from zmpkit.robots.teo import fit_catalogue
from zmpkit.robots.teo import geometry as geo
from zmpkit.robots.teo.fit_fields import TEO_FIELD_RULE
from zmpkit.robots.teo.model import (
    TEO_BALANCE_MASS_KG,
    TEO_COM_HEIGHT_M,
    TEO_DRIVEN_JOINTS,
    teo_feet_mounts,
)
from zmpkit.robots.teo.robot import TEO_SERVO_LIMITS, teo_robot
from zmpkit.robots.teo.truth import DEFAULT_TRUTH_PATH, TeoTruth, load_truth, truth_from_doc
from zmpkit.sensors.zmp import CONTACT_FORCE_THRESHOLD_N
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.world import Simulation

__all__ = ["TEO", "make_teo"]


def _support_polygon() -> dict[str, tuple[float, float]]:
    """Double-support extent of the soles per plane, from the design [m]."""
    half_width = abs(teo_feet_mounts()["left"]["position"][1]) + geo.SOLE_WIDTH_M / 2
    return {
        "sagittal": (-geo.HEEL_TO_ANKLE_M, geo.ANKLE_TO_TOE_M),
        "frontal": (-half_width, half_width),
    }


TEO = Robot(
    name="teo",
    title="TEO",
    summary="UC3M TEO, 62.6 kg adult-size humanoid (paper A): standing balance, push recovery",
    source="teo",
    describe=teo_robot,
    driven_joints=TEO_DRIVEN_JOINTS,
    feet_mounts=teo_feet_mounts,
    truth=TruthSpec(DEFAULT_TRUTH_PATH, load_truth, truth_from_doc, TeoTruth),
    servo_limits=TEO_SERVO_LIMITS,
    contact_force_threshold_n=CONTACT_FORCE_THRESHOLD_N,
    balance=BalanceModel(
        mass_kg=TEO_BALANCE_MASS_KG,
        com_height_m=TEO_COM_HEIGHT_M,
        support_polygon_m=_support_polygon(),
        lean_joints={
            "sagittal": ("right_ankle_frontal", "left_ankle_frontal"),
            "frontal": ("right_ankle_sagittal", "left_ankle_sagittal"),
        },
        hip_roll_joints=("right_hip_sagittal", "left_hip_sagittal"),
        push_bodies={"com": "root_waist", "trunk": "trunk_frontal"},
        control_period_s=0.01,
        target_span_m=0.10,  # paper A's Table 1: working points 0 ... 0.10 m
    ),
    fit=FitSpec(
        fit_catalogue.FIT_CATALOGUE, fit_catalogue.QUICK_FIT_PARAMETERS, "step", TEO_FIELD_RULE
    ),
)
"""The virtual TEO."""


def make_teo(
    effects: EffectSet | str = "all",
    truth: TeoTruth | str | Path | None = None,
    seed: int = 0,
) -> Simulation:
    """:data:`TEO`'s :meth:`~zmpkit.robots.robot.Robot.make_simulation`, standing in its zero pose.

    The robot starts with unloaded springs and settles within about 2 s with all effects
    on (the lean mode is lightly damped on purpose); with gear compliance but the ideal
    servo (``"G"``, ``"G,F"``) allow about 6 s. Measure the start-up offset after that.
    """
    return TEO.make_simulation(effects, truth, seed)
