"""Assemble the virtual TEO: its rigid MJCF, the switched-on effects, and a simulation.

:func:`teo_robot` gives the :class:`~zmpkit.sim.description.RobotDescription` (MJCF with the
effects applied, driven joints, foot sensors, IMU, servo limits); a simulation of it is
:meth:`TEO.make_simulation <zmpkit.robots.robot.Robot.make_simulation>`. The truth parameters
come from :func:`~zmpkit.robots.teo.truth.load_truth` (the shipped file unless one is given).
"""

from __future__ import annotations

from pathlib import Path

from zmpkit.robots.teo import geometry as geo
from zmpkit.robots.teo.model import TEO_DRIVEN_JOINTS, TEO_SIDES, base_mjcf
from zmpkit.robots.teo.truth import TeoTruth, load_truth
from zmpkit.sim.builder import add_ideal_servo
from zmpkit.sim.description import FootSensor, RobotDescription
from zmpkit.sim.drive import IdealServoParams
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.joint_effects import add_drive_effects, mjcf_with_flex
from zmpkit.sim.servo import ServoLimits

__all__ = ["TEO_SERVO_LIMITS", "teo_mjcf", "teo_robot"]

TEO_SERVO_LIMITS = ServoLimits(max_velocity=0.35, max_acceleration=0.1, synchronized=True)
"""Setpoint trajectory limits of TEO's drives (20 °/s, 5.7 °/s²; assumed, not in the
parameters file). Synchronized: the joints of one command move in proportion and arrive
together, as the host's cyclic-synchronous-position interpolation does; a frontal lean
closes a loop through both legs and the floor (see :mod:`zmpkit.robots.teo.lean`)."""


def _resolve_truth(truth: TeoTruth | str | Path | None) -> TeoTruth:
    return truth if isinstance(truth, TeoTruth) else load_truth(truth)


def teo_mjcf(effects: EffectSet | str = "all", truth: TeoTruth | str | Path | None = None) -> str:
    """TEO's MJCF text with the chosen effects applied.

    Args:
        effects: ``"all"``, ``"none"``, letters such as ``"M,G,S"``, or an EffectSet.
        truth: truth parameters, a truth file, or ``None`` for the shipped truth.
    """
    on = EffectSet.parse(effects)
    params = _resolve_truth(truth)
    root = base_mjcf(params)
    for joint in TEO_DRIVEN_JOINTS:
        gear = params.gear if joint in params.gear_joints else None
        if not add_drive_effects(root, joint, on, params.motors, params.inductances, gear):
            add_ideal_servo(root, joint, IdealServoParams())
    return mjcf_with_flex(root, on, params.flex)


def teo_robot(
    effects: EffectSet | str,
    truth: TeoTruth | str | Path | None,
    contact_force_threshold_n: float,
) -> RobotDescription:
    """The virtual TEO as a robot description, ready for :class:`~zmpkit.sim.world.Simulation`.

    TEO's :attr:`~zmpkit.robots.robot.Robot.describe`: ``effects`` as
    :meth:`~zmpkit.sim.effect_set.EffectSet.parse` reads them, ``truth`` the truth parameters,
    a truth file or ``None`` (the shipped truth), and the robot's contact threshold [N].
    """
    on = EffectSet.parse(effects)
    params = _resolve_truth(truth)
    feet = tuple(FootSensor.named(side, geo.FT_HEIGHT_ABOVE_SOLE_M) for side in TEO_SIDES)
    return RobotDescription(
        name="teo",
        mjcf=teo_mjcf(on, params),
        driven_joints=TEO_DRIVEN_JOINTS,
        feet=feet,
        effects=on,
        contact_force_threshold_n=contact_force_threshold_n,
        servo_limits=TEO_SERVO_LIMITS,
        sensor_params=params.sensors,
        ft_offsets=params.ft_offsets,
        ft_gain_errors=params.ft_gain_errors,
        variability=params.variability,
    )
