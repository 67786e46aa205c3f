r"""``zmpkit robot check``: load a robot, stand it, and compare its three ZMPs.

The robot stands ``stand_s`` with every effect off (ideal servos holding the initial pose).
Then, from the last sample:

- the **F-T ZMP**: from the virtual F-T sensors' wrenches (what a user's robot measures),
  :func:`~zmpkit.sensors.zmp.zmp_in_world`;
- the **contact ZMP**: the centre of pressure of MuJoCo's contact forces on the floor,
  :math:`p = \sum_i p_i f_{z,i} / \sum_i f_{z,i}` over the contact points :math:`p_i` (on the
  floor plane, so the tangential forces have no moment about it);
- the **CoM projection**: where the ZMP of a static robot is.

They agree to about a millimetre on a correct robot; a larger gap points at F-T sensors that
do not carry the whole foot (a foot geom still touching the floor) or a robot not at rest.

It also checks the guesses a robot file rests on: the left foot stands to the left of the
right one (world +y, the robot facing +x), and flexing the knees carries the feet backwards
(world −x; :func:`~zmpkit.robots.facing.knee_flexion`, where the knees bend one way only):
feet swapped, or a wrong ``forward:``, fail.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from zmpkit.errors import ParameterError
from zmpkit.robots.facing import knee_flexion
from zmpkit.robots.robot import Robot
from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sim.names import sole_site

__all__ = ["RobotCheck", "check_robot", "require_passing_check"]

AGREEMENT_M = 0.002
"""The three ZMPs of a robot at rest agree within this [m]."""


@dataclass(frozen=True)
class RobotCheck:
    """What ``zmpkit robot check`` reports.

    Attributes:
        name: the robot's name.
        mass_kg: total mass [kg].
        com_height_m: CoM height after standing [m].
        feet: foot → its F-T sensor site's position (x, y, z) [m].
        sensor_heights_m: foot → F-T sensor height above the sole [m].
        sensors: the MuJoCo sensors' names.
        driven_joints: the servo-driven joints, in order.
        zmp_ft_m: ZMP from the F-T sensors (x, y) [m].
        zmp_contact_m: ZMP from MuJoCo's contact forces (x, y) [m].
        com_xy_m: the CoM's ground projection (x, y) [m].
        stood_s: how long it stood [s].
        left_of_right_m: how far the left sole centre stands left (world +y) of the right
            one [m]; None for a robot without both feet.
        excluded_contacts: the pairs of bodies whose contacts the model excludes (an
            imported model's links overlapping at the initial pose).
        self_contacts: contacts between two of the robot's bodies after standing.
        self_contact_force_n: the largest normal force of those [N]; 0 without any.
        knee_shift_x_m: how far flexing the knees carries the feet along world x, averaged
            over the feet [m]: negative (backwards) on a robot facing +x; None when its knees
            do not bend one way only.
        knees: the knee joints flexed.
    """

    name: str
    mass_kg: float
    com_height_m: float
    feet: dict[str, tuple[float, float, float]]
    sensor_heights_m: dict[str, float]
    sensors: tuple[str, ...]
    driven_joints: tuple[str, ...]
    zmp_ft_m: tuple[float, float]
    zmp_contact_m: tuple[float, float]
    com_xy_m: tuple[float, float]
    stood_s: float
    left_of_right_m: float | None = None
    excluded_contacts: tuple[tuple[str, str], ...] = ()
    self_contacts: int = 0
    self_contact_force_n: float = 0.0
    knee_shift_x_m: float | None = None
    knees: tuple[str, ...] = ()

    @property
    def ft_vs_contact_m(self) -> float:
        """Distance between the F-T and the contact ZMP [m]."""
        return float(np.hypot(*np.subtract(self.zmp_ft_m, self.zmp_contact_m)))

    @property
    def ft_vs_com_m(self) -> float:
        """Distance between the F-T ZMP and the CoM projection [m]."""
        return float(np.hypot(*np.subtract(self.zmp_ft_m, self.com_xy_m)))

    @property
    def feet_sides_ok(self) -> bool:
        """Whether the left foot stands left of the right one (or the robot has no pair)."""
        return self.left_of_right_m is None or self.left_of_right_m > 0.0

    @property
    def knees_ok(self) -> bool:
        """Whether flexing the knees carries the feet backwards (or the knees cannot tell)."""
        return self.knee_shift_x_m is None or self.knee_shift_x_m < 0.0

    @property
    def zmps_agree(self) -> bool:
        """Whether the three ZMPs agree within :data:`AGREEMENT_M`."""
        return max(self.ft_vs_contact_m, self.ft_vs_com_m) <= AGREEMENT_M

    @property
    def ok(self) -> bool:
        """Whether the ZMPs agree, the feet stand on their sides and the knees bend forwards."""
        return self.zmps_agree and self.feet_sides_ok and self.knees_ok

    def lines(self) -> list[str]:
        """The report, one line per item."""
        verdict = "OK" if self.zmps_agree else f"MISMATCH (> {1e3 * AGREEMENT_M:g} mm)"
        feet = "; ".join(
            f"{f} sensor at ({x:.4f}, {y:.4f}, {z:.4f}) m, {1e3 * self.sensor_heights_m[f]:.1f} mm "
            "above the sole"
            for f, (x, y, z) in self.feet.items()
        )
        return [
            f"robot {self.name}: mass {self.mass_kg:.4g} kg, CoM height {self.com_height_m:.4f} m "
            f"after standing {self.stood_s:g} s",
            f"feet: {feet}",
            f"driven joints: {', '.join(self.driven_joints)}",
            f"sensors: {', '.join(self.sensors)}",
            f"ZMP from the F-T sensors ({self.zmp_ft_m[0]:.4f}, {self.zmp_ft_m[1]:.4f}) m, from "
            f"MuJoCo's contact forces ({self.zmp_contact_m[0]:.4f}, {self.zmp_contact_m[1]:.4f}) "
            f"m, CoM projection ({self.com_xy_m[0]:.4f}, {self.com_xy_m[1]:.4f}) m",
            f"F-T vs contact {1e3 * self.ft_vs_contact_m:.2f} mm, F-T vs CoM "
            f"{1e3 * self.ft_vs_com_m:.2f} mm: {verdict}",
            *self._sides_line(),
            *self._knees_line(),
            *self._contacts_lines(),
        ]

    def _contacts_lines(self) -> list[str]:
        lines = []
        if self.excluded_contacts:
            pairs = ", ".join(f"{a}–{b}" for a, b in self.excluded_contacts)
            lines.append(
                f"excluded self-contacts ({len(self.excluded_contacts)} pairs of links touching "
                f"at the initial pose): {pairs}"
            )
        lines.append(
            f"self-contacts after standing: {self.self_contacts}"
            + (f", largest {self.self_contact_force_n:.3g} N" if self.self_contacts else "")
        )
        return lines

    def _sides_line(self) -> list[str]:
        if self.left_of_right_m is None:
            return []
        side = "left" if self.left_of_right_m > 0.0 else "RIGHT"
        verdict = (
            "OK"
            if self.feet_sides_ok
            else "MISMATCH (feet swapped, or the robot does not face +x: check feet and forward)"
        )
        return [
            f"left foot {1e3 * abs(self.left_of_right_m):.1f} mm to the {side} of the right "
            f"foot, facing +x: {verdict}"
        ]

    def _knees_line(self) -> list[str]:
        if self.knee_shift_x_m is None:
            return ["knees: none bends one way only, so they cannot show forward"]
        way = "backwards" if self.knee_shift_x_m < 0.0 else "FORWARDS"
        verdict = "OK" if self.knees_ok else "MISMATCH (the robot does not face +x: check forward)"
        return [
            f"flexing {' and '.join(self.knees)} carries the feet "
            f"{1e3 * abs(self.knee_shift_x_m):.0f} mm {way}, facing +x: {verdict}"
        ]


def _knee_shift(
    model: mujoco.MjModel, qpos: np.ndarray, bodies: list[int]
) -> tuple[float | None, tuple[str, ...]]:
    """The feet's mean shift along world x when their knees flex [m], and the knees."""
    flexed = [knee_flexion(model, qpos, b) for b in bodies]
    bent = [k for k in flexed if k is not None]
    if not bent:
        return None, ()
    return float(np.mean([k.foot_shift_m[0] for k in bent])), tuple(k.joint for k in bent)


def _contact_zmp(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[float, float]:
    """Centre of pressure of the floor contacts [m] (module docstring)."""
    force = np.zeros(6)
    total, moment = 0.0, np.zeros(2)
    for i in range(data.ncon):
        contact = data.contact[i]
        mujoco.mj_contactForce(model, data, i, force)
        normal_z = abs(float(contact.frame[2])) * force[0]  # normal force's vertical part [N]
        total += normal_z
        moment += normal_z * contact.pos[:2]
    return (float(moment[0] / total), float(moment[1] / total)) if total > 0 else (np.nan, np.nan)


def _xyz(vector: np.ndarray) -> tuple[float, float, float]:
    return (float(vector[0]), float(vector[1]), float(vector[2]))


def check_robot(robot: Robot, stand_s: float = 2.0) -> RobotCheck:
    """Stand ``robot`` for ``stand_s`` [s] with the effects off and report (module docstring)."""
    sim = robot.make_simulation("none")
    soles = [sim.model.site(sole_site(f.foot)).bodyid.item() for f in sim.robot.feet]
    knee_shift_x_m, knees = _knee_shift(sim.model, sim.data.qpos.copy(), soles)
    sim.step(max(1, round(stand_s / sim.dt)))
    model, data = sim.model, sim.data
    feet = sim.robot.feet
    sites = [data.site(f.site) for f in feet]
    xmat = np.array([s.xmat for s in sites])
    force, moment = wrench_in_world(xmat, np.array([sim.ft(f.foot) for f in feet]))
    origin = np.array([s.xpos for s in sites])
    zmp = zmp_in_world(force[None], moment[None], origin[None], robot.contact_force_threshold_n)[0]
    names = tuple(model.sensor(i).name for i in range(model.nsensor))
    touching, largest_n = _self_contacts(model, data)
    return RobotCheck(
        name=robot.name,
        mass_kg=float(model.body_subtreemass[0]),
        com_height_m=float(data.subtree_com[0][2]),
        feet={f.foot: _xyz(s.xpos) for f, s in zip(feet, sites, strict=True)},
        sensor_heights_m={f.foot: f.sole_height_m for f in feet},
        sensors=names,
        driven_joints=tuple(sim.joint_names),
        zmp_ft_m=(float(zmp[0]), float(zmp[1])),
        zmp_contact_m=_contact_zmp(model, data),
        com_xy_m=(float(data.subtree_com[0][0]), float(data.subtree_com[0][1])),
        stood_s=sim.time,
        left_of_right_m=_left_of_right(model, data),
        excluded_contacts=_excluded(model),
        self_contacts=touching,
        self_contact_force_n=largest_n,
        knee_shift_x_m=knee_shift_x_m,
        knees=knees,
    )


def _excluded(model: mujoco.MjModel) -> tuple[tuple[str, str], ...]:
    """The model's ``<exclude>`` pairs of body names (signature: body1 << 16 | body2)."""
    pairs = []
    for signature in model.exclude_signature[: model.nexclude]:
        a, b = model.body(int(signature) >> 16).name, model.body(int(signature) & 0xFFFF).name
        pairs.append((min(a, b), max(a, b)))
    return tuple(sorted(pairs))


def _self_contacts(model: mujoco.MjModel, data: mujoco.MjData) -> tuple[int, float]:
    """How many contacts join two of the robot's bodies, and the largest normal force [N]."""
    count, largest = 0, 0.0
    wrench = np.zeros(6)
    for k in range(data.ncon):
        contact = data.contact[k]
        first, second = (int(model.geom_bodyid[g]) for g in (contact.geom1, contact.geom2))
        if first == 0 or second == 0 or first == second:
            continue
        mujoco.mj_contactForce(model, data, k, wrench)
        count += 1
        largest = max(largest, abs(float(wrench[0])))
    return count, largest


def _left_of_right(model: mujoco.MjModel, data: mujoco.MjData) -> float | None:
    sites = {mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, i) for i in range(model.nsite)}
    if not {sole_site("left"), sole_site("right")} <= sites:
        return None
    return float(data.site(sole_site("left")).xpos[1] - data.site(sole_site("right")).xpos[1])


def require_passing_check(robot: Robot, reference: str) -> RobotCheck:
    """``robot``'s check (:func:`check_robot`), refused with one line when it fails.

    A command that runs a user's robot (``reference``: its ``robot.yaml``) runs the check
    first: F-T sensors that do not carry the whole foot, or a robot that does not come to
    rest, would make every ZMP it measures wrong. Checked once per file and modification
    time in a process.

    Raises:
        ParameterError: naming the file, the gaps and the command that shows the details.
    """
    path = Path(reference)
    key = (str(path.resolve()), path.stat().st_mtime_ns if path.exists() else 0)
    result = _CHECKED.get(key)
    if result is None:
        result = _CHECKED[key] = check_robot(robot)
    if not result.ok:
        reasons = []
        if not result.zmps_agree:
            reasons.append(
                f"the F-T ZMP lies {1e3 * result.ft_vs_contact_m:.1f} mm from the contact ZMP and "
                f"{1e3 * result.ft_vs_com_m:.1f} mm from the CoM projection (at rest both within "
                f"{1e3 * AGREEMENT_M:g} mm)"
            )
        if not result.knees_ok and result.knee_shift_x_m is not None:
            reasons.append(
                f"flexing its knees carries its feet {1e3 * result.knee_shift_x_m:.0f} mm "
                "forwards (a wrong forward:)"
            )
        if not result.feet_sides_ok and result.left_of_right_m is not None:
            reasons.append(
                f"its left foot stands {1e3 * -result.left_of_right_m:.1f} mm right of its right "
                "foot (feet swapped, or a wrong forward:)"
            )
        raise ParameterError(
            f"{reference} fails its robot check: {'; '.join(reasons)}; "
            f"`zmpkit robot check {reference}` shows the details"
        )
    return result


_CHECKED: dict[tuple[str, int], RobotCheck] = {}
"""Checks run in this process, by robot file (resolved path, modification time [ns])."""
