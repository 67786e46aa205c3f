"""Simulation layer: the effects (M, I, G, F, S) shared by every virtual robot, and the world.

Only this layer and :mod:`zmpkit.robots` import MuJoCo.
"""

from zmpkit.sim.compliance import FlexJoint, GearParams
from zmpkit.sim.description import FootSensor, ImuSensors, RobotDescription
from zmpkit.sim.drive import IdealServoParams, InductanceParams, MotorParams
from zmpkit.sim.effect_set import EFFECT_LETTERS, EffectSet
from zmpkit.sim.sensor_errors import SensorParams
from zmpkit.sim.servo import ServoLimits, TrajectoryLimiter
from zmpkit.sim.spring import SofteningSpring
from zmpkit.sim.world import Simulation

__all__ = [
    "EFFECT_LETTERS",
    "EffectSet",
    "FlexJoint",
    "FootSensor",
    "GearParams",
    "IdealServoParams",
    "ImuSensors",
    "InductanceParams",
    "MotorParams",
    "RobotDescription",
    "SensorParams",
    "ServoLimits",
    "Simulation",
    "SofteningSpring",
    "TrajectoryLimiter",
]
