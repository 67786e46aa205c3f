"""Parameters of the simulated compliances, in SI units: gears (G) and flexible links (F).

Paper B §II, MoToFlex: gears with flexibility and tolerance (backlash) between the motor side
and the link side; flexible links as passive compliant joints. Angles and torques named
``*_link`` are on the joint (output) side of the gear.

Defaults are plausible values for a ~60 kg humanoid; a robot overrides them from its truth
file. How each effect is simulated is in :mod:`zmpkit.sim.builder`.
"""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit._validate import finite, non_negative, positive
from zmpkit.errors import ParameterError
from zmpkit.sim.spring import SofteningSpring

__all__ = ["FlexJoint", "GearParams"]


@dataclass(frozen=True)
class GearParams:
    """Torsional compliance and backlash between the motor side and the link side.

    The transmitted torque is zero while the deflection ``q_link - q_motor / N`` lies inside
    the dead band ``[-backlash/2, +backlash/2]`` and ``stiffness`` times the excess outside
    it, plus ``damping`` times the deflection rate.

    Attributes:
        stiffness: torsional stiffness at the link [N·m/rad].
        damping: torsional damping at the link [N·m·s/rad].
        backlash: total dead-band width at the link [rad].
        inertia_link: inertia of the gear train on the motor side, seen at the joint
            [kg·m²]; gives the motor-side joint mass when the motor effect is off.
    """

    stiffness: float = 30000.0
    damping: float = 30.0
    backlash: float = 0.002
    inertia_link: float = 0.05

    def __post_init__(self) -> None:
        positive("GearParams.stiffness", self.stiffness, "N·m/rad")
        non_negative("GearParams.damping", self.damping, "N·m·s/rad")
        non_negative("GearParams.backlash", self.backlash, "rad")
        positive("GearParams.inertia_link", self.inertia_link, "kg·m²")


@dataclass(frozen=True)
class FlexJoint:
    """A passive compliant joint that stands for structural flexibility at one place.

    Two spring laws, plus ``-damping * x_dot``:

    - polynomial (``softening_torque = 0``): ``tau = -(k1 x + k2 x**2 + k3 x**3)`` in the
      deflection ``x`` [rad] (MuJoCo's polynomial joint spring). With ``k2 < 0 < k3`` and
      ``k2**2 < 3 k1 k3`` it softens and stiffens again, staying monotonic.
    - softening (``softening_torque > 0``): the law of
      :class:`~zmpkit.sim.spring.SofteningSpring` with ``k0 = k1``, symmetric and monotonic,
      built from native tendon springs; ``k2`` and ``k3`` must then be 0.

    Attributes:
        name: joint name in the model, e.g. ``"right_foot_pitch_flex"``.
        body: name of the body the joint is added to (the compliant part's child side).
        axis: joint axis in the body frame [-].
        anchor: joint position in the body frame [m].
        stiffness: ``(k1, k2, k3)`` in [N·m/rad], [N·m/rad²], [N·m/rad³].
        damping: viscous damping [N·m·s/rad].
        softening_torque: ``τ_s`` of the softening law [N·m]; 0 = polynomial spring.
        softening_torque_range: torque up to which the native approximation follows the
            softening law [N·m].
        softening_stages: number of linear segments of that approximation [-].
    """

    name: str
    body: str
    axis: tuple[float, float, float]
    anchor: tuple[float, float, float] = (0.0, 0.0, 0.0)
    stiffness: tuple[float, float, float] = (20000.0, 0.0, 0.0)
    damping: float = 50.0
    softening_torque: float = 0.0
    softening_torque_range: float = 50.0
    softening_stages: int = 6

    def __post_init__(self) -> None:
        k1, k2, k3 = (finite(f"FlexJoint {self.name} stiffness", k) for k in self.stiffness)
        positive(f"FlexJoint {self.name} stiffness k1", k1, "N·m/rad")
        non_negative(f"FlexJoint {self.name} stiffness k3", k3, "N·m/rad³")
        if k2 * k2 >= 3.0 * k1 * k3 and k2 != 0.0:
            raise ParameterError(
                f"FlexJoint {self.name}: stiffness (k1, k2, k3) = {self.stiffness} is not "
                "monotonic; need k2**2 < 3 k1 k3 so the spring never buckles"
            )
        non_negative(f"FlexJoint {self.name} damping", self.damping, "N·m·s/rad")
        non_negative(f"FlexJoint {self.name} softening_torque", self.softening_torque, "N·m")
        if self.softening_torque > 0.0 and (k2 != 0.0 or k3 != 0.0):
            raise ParameterError(
                f"FlexJoint {self.name}: a softening spring (softening_torque > 0) replaces "
                f"the polynomial; stiffness must be (k1, 0, 0), got {self.stiffness}"
            )
        self.spring  # noqa: B018 - validates the softening parameters

    @property
    def spring(self) -> SofteningSpring | None:
        """The softening law, or None for a polynomial spring."""
        if self.softening_torque == 0.0:
            return None
        return SofteningSpring(
            self.stiffness[0],
            self.softening_torque,
            self.softening_torque_range,
            self.softening_stages,
        )

    def torque(self, deflection: float) -> float:
        """Static spring torque the joint carries at a deflection [N·m]."""
        spring = self.spring
        if spring is not None:
            return spring.torque(deflection)
        k1, k2, k3 = self.stiffness
        return k1 * deflection + k2 * deflection**2 + k3 * deflection**3
