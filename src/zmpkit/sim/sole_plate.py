"""MJCF of a sole plate under an ankle F-T sensor, shared by the virtual robots.

The plate is the body below the sensor: its frame is the sensor frame (the ``zmpkit/{side}_ft``
site, x forward, y left, z up), and its box geom is the foot's contact with the floor.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from zmpkit.sim.names import ft_site, sole_geom

__all__ = ["SolePlate", "add_sole_plate"]


@dataclass(frozen=True)
class SolePlate:
    """A sole plate's geometry and contact.

    Attributes:
        length_m: sole length along x [m].
        width_m: sole width along y [m].
        height_m: plate thickness = height of the F-T sensor frame above the sole [m].
        centre_x_m: sole centre ahead of the sensor frame [m].
        mass_kg: plate mass (below the sensor, so the sensor does not weigh it) [kg].
        friction: sliding friction coefficient with the floor [-].
        solref: MuJoCo contact ``solref`` of the sole.
        solimp: MuJoCo contact ``solimp`` of the sole.
    """

    length_m: float
    width_m: float
    height_m: float
    centre_x_m: float
    mass_kg: float
    friction: float
    solref: str
    solimp: str


def _f(*values: float) -> str:
    return " ".join(f"{v:.9g}" for v in values)


def add_sole_plate(sole: ET.Element, side: str, plate: SolePlate, centre_site: str) -> None:
    """Add the contact box, the ``zmpkit/{side}_ft`` site and a sole-centre site to body ``sole``.

    ``priority`` 1 makes the sole's own contact parameters win over the floor's, instead of
    MuJoCo averaging them. Its collision attributes are explicit (``contype``,
    ``conaffinity``, ``condim`` 3, no margin), so a model whose defaults switch collisions
    off or make them frictionless (Menagerie's Apollo: every geom ``contype`` 0, ``condim``
    1) does not pass them on to the plate.
    """
    h = plate.height_m
    ET.SubElement(
        sole,
        "geom",
        {
            "name": sole_geom(side),
            "type": "box",
            "pos": _f(plate.centre_x_m, 0.0, -0.5 * h),
            "size": _f(0.5 * plate.length_m, 0.5 * plate.width_m, 0.5 * h),
            "mass": _f(plate.mass_kg),
            "friction": _f(plate.friction, 0.005, 0.0001),
            "solref": plate.solref,
            "solimp": plate.solimp,
            "priority": "1",
            "contype": "1",
            "conaffinity": "1",
            "condim": "3",
            "margin": "0",
            "gap": "0",
            "rgba": "0.3 0.3 0.35 1",
        },
    )
    ET.SubElement(sole, "site", {"name": ft_site(side), "pos": "0 0 0", "size": "0.005"})
    ET.SubElement(
        sole, "site", {"name": centre_site, "pos": _f(plate.centre_x_m, 0, -h), "size": "0.005"}
    )
