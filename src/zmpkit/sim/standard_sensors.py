"""The standard sensor section every robot model of zmpkit carries.

Each foot's 6-axis F-T sensor (MuJoCo ``force`` and ``torque`` at the foot's F-T site,
:func:`~zmpkit.sim.names.ft_site`) and the IMU (``gyro``, ``accelerometer`` and
``framequat`` at :data:`~zmpkit.sim.names.IMU_SITE`), under the names
:class:`~zmpkit.sim.description.FootSensor` and :class:`~zmpkit.sim.description.ImuSensors`
read them by.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence

from zmpkit.sim.description import FootSensor, ImuSensors
from zmpkit.sim.names import IMU_SITE

__all__ = ["add_standard_sensors"]


def add_standard_sensors(root: ET.Element, feet: Sequence[str]) -> ET.Element:
    """Append the ``<sensor>`` section for ``feet`` (e.g. ``("right", "left")``) to ``root``.

    The sites must exist in the model: each foot's F-T site and the IMU site.
    """
    sensors = ET.SubElement(root, "sensor")
    for foot in feet:
        named = FootSensor.named(foot, 0.0)
        ET.SubElement(sensors, "force", {"name": named.force_sensor, "site": named.site})
        ET.SubElement(sensors, "torque", {"name": named.torque_sensor, "site": named.site})
    imu = ImuSensors()
    ET.SubElement(sensors, "gyro", {"name": imu.gyro, "site": IMU_SITE})
    ET.SubElement(sensors, "accelerometer", {"name": imu.accelerometer, "site": IMU_SITE})
    ET.SubElement(
        sensors, "framequat", {"name": imu.orientation, "objtype": "site", "objname": IMU_SITE}
    )
    return sensors
