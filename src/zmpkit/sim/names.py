"""The names zmpkit gives to what it adds to a robot's model, in their own namespace.

A robot's model is the user's: its bodies, sites and geoms keep the names it gave them, and
anything zmpkit adds to it (the sole plates with their F-T sites, the sole-centre sites, the
IMU site, the floor) is named under :data:`NAMESPACE`, so a model that has its own site
``imu`` or geom ``floor`` goes in unedited. zmpkit's sensors and actuators keep plain names
(``right_ft_force``, ``imu_gyro``, the joint's name): zmpkit writes a model's whole sensor and
actuator sections, replacing the model's own, so nothing of the model's can collide there.
"""

from __future__ import annotations

__all__ = [
    "FLOOR_GEOM",
    "IMU_SITE",
    "NAMESPACE",
    "ft_plate_body",
    "ft_site",
    "sole_geom",
    "sole_site",
]

NAMESPACE = "zmpkit/"
"""The prefix of every body, site and geom zmpkit adds to a model."""

IMU_SITE = f"{NAMESPACE}imu"
"""The site the IMU's gyro, accelerometer and orientation sensors sit at."""

FLOOR_GEOM = f"{NAMESPACE}floor"
"""The floor plane zmpkit adds where the model has none."""


def ft_site(foot: str) -> str:
    """The F-T sensor's site of ``foot`` (its frame is the sensor frame)."""
    return f"{NAMESPACE}{foot}_ft"


def sole_site(foot: str) -> str:
    """The site at the centre of ``foot``'s sole, on the sole plane."""
    return f"{NAMESPACE}{foot}_sole"


def sole_geom(foot: str) -> str:
    """The contact box of ``foot``'s sole plate."""
    return f"{NAMESPACE}{foot}_sole"


def ft_plate_body(foot: str) -> str:
    """The body zmpkit adds under a user's foot: the sole plate below its F-T sensor."""
    return f"{NAMESPACE}{foot}_ft_plate"
