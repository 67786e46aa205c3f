"""Which of the simulated effects are switched on.

The letters follow the MoToFlex paper (paper B §II) plus one for sensors:

- ``M`` motor: DC motor, gear ratio, reflected rotor inertia, friction and the joint PID.
- ``I`` winding inductance (electrical time constant L/R); needs ``M``.
- ``G`` gears: torsional stiffness, damping and backlash between motor and link.
- ``F`` flexible structure: passive compliant joints at named places.
- ``S`` sensors: F-T offset, gain error, noise, quantisation, filter, sample rate; encoder
  resolution; IMU noise.

With everything off the robot is rigid, its joints are ideal (a stiff PID servo with
integral action holds every commanded angle exactly) and its sensors are perfect.
"""

from __future__ import annotations

from dataclasses import dataclass

from zmpkit.errors import ParameterError

__all__ = ["EFFECT_LETTERS", "EffectSet"]

EFFECT_LETTERS: dict[str, str] = {
    "M": "motor (DC motor, gear ratio, rotor inertia, friction, PID)",
    "I": "winding inductance",
    "G": "gear flexibility and backlash",
    "F": "flexible structure",
    "S": "sensor errors",
}


@dataclass(frozen=True)
class EffectSet:
    """A set of switched-on effects.

    Attributes:
        motor: ``M`` is on.
        inductance: ``I`` is on.
        gear: ``G`` is on.
        flex: ``F`` is on.
        sensors: ``S`` is on.
    """

    motor: bool = False
    inductance: bool = False
    gear: bool = False
    flex: bool = False
    sensors: bool = False

    @classmethod
    def all(cls) -> EffectSet:
        """Every effect on."""
        return cls(True, True, True, True, True)

    @classmethod
    def none(cls) -> EffectSet:
        """Every effect off: rigid robot, ideal joints, perfect sensors."""
        return cls()

    @classmethod
    def parse(cls, text: str | EffectSet) -> EffectSet:
        """Parse ``"all"``, ``"none"`` or a comma-separated list of letters such as ``"M,G,S"``.

        Letters are case-insensitive; spaces are ignored; an empty string means ``"none"``.

        Raises:
            ParameterError: on an unknown letter, naming the valid ones.
        """
        if isinstance(text, EffectSet):
            return text
        if not isinstance(text, str):
            raise ParameterError(f"effects must be a string such as 'all', got {text!r}")
        word = text.strip().lower()
        if word == "all":
            return cls.all()
        if word in ("none", ""):
            return cls.none()
        letters = [part.strip().upper() for part in word.split(",") if part.strip()]
        unknown = [x for x in letters if x not in EFFECT_LETTERS]
        if unknown:
            valid = ", ".join(f"{k} ({v})" for k, v in EFFECT_LETTERS.items())
            raise ParameterError(
                f"unknown effect {', '.join(repr(u) for u in unknown)} in {text!r}; "
                f"expected 'all', 'none' or comma-separated letters from: {valid}"
            )
        on = set(letters)
        return cls("M" in on, "I" in on, "G" in on, "F" in on, "S" in on)

    @property
    def letters(self) -> str:
        """The canonical text form: ``"all"``, ``"none"`` or e.g. ``"M,G,S"``."""
        flags = (self.motor, self.inductance, self.gear, self.flex, self.sensors)
        on = [k for k, f in zip(EFFECT_LETTERS, flags, strict=True) if f]
        if len(on) == len(EFFECT_LETTERS):
            return "all"
        return ",".join(on) if on else "none"

    def __str__(self) -> str:
        return self.letters
