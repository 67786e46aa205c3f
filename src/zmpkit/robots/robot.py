"""A robot as every pipeline takes it: model, description, balance and walking defaults, truth.

A :class:`Robot` is what the registry (:mod:`zmpkit.robots.registry`) gives for a built-in
name or a user's ``robot.yaml``. Pipelines never branch on a robot's name: they ask the robot.

- **description** — :meth:`Robot.description` is the simulator's
  :class:`~zmpkit.sim.description.RobotDescription` (MJCF with the chosen effects, driven joints
  in order, foot F-T sensors with their heights above the sole, IMU, servo limits, contact
  threshold); :meth:`Robot.make_simulation` starts a :class:`~zmpkit.sim.world.Simulation`.
- **balance** — :class:`BalanceModel`: the pendulum a balance controller believes (mass, CoM
  height), the support polygon and the joints of the ankle-strategy lean.
- **walking** — :class:`WalkingDefaults`: CoM height, foot spacing, step limits, the rigid IK
  model and the IK's frames and posture (:class:`~zmpkit.robots.ik_settings.IkSettings`).
- **truth** — :class:`TruthSpec`: the shipped truth file and its loaders (the simulator's hidden
  parameters); **fit** — :class:`FitSpec`: the simulator fit's parameter catalogue.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Generic, TypeVar, cast

import mujoco

from zmpkit.errors import ParameterError
from zmpkit.robots.field_rule import FieldRule
from zmpkit.robots.fit_parameter import FitParameter
from zmpkit.robots.ik_settings import IkSettings
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.effect_set import EffectSet
from zmpkit.sim.servo import ServoLimits
from zmpkit.sim.truth_file import RobotTruth
from zmpkit.sim.world import Simulation

if TYPE_CHECKING:
    from zmpkit.io.feet import FootMountEntry

__all__ = [
    "DEFAULT_WALK_SPEED_MPS",
    "TARGET_SUPPORT_SHARE",
    "BalanceModel",
    "FitSpec",
    "Robot",
    "TruthSpec",
    "WalkingDefaults",
]

TARGET_SUPPORT_SHARE = 0.3
"""A robot's largest balance target, as a share of the nearest support-polygon edge [-]: a
soft-servo robot's ZMP overshoots a lean step by up to its target and settles beyond it, so
twice the target must stay on the sole with room to spare. (Paper A's TEO, with stiff
servos, was run to 0.57 of its edge: 0.10 m of 0.175 m; its preset says so.)"""

DEFAULT_WALK_SPEED_MPS = 0.2
"""A robot's default walking speed unless it gives its own [m/s]: paper B's 20 cm/s walk."""

TruthT = TypeVar("TruthT", bound=RobotTruth)
"""The class of a robot's truth object (its own frozen dataclass, a
:class:`~zmpkit.sim.truth_file.RobotTruth`); only its robot reads its fields."""


@dataclass(frozen=True, eq=False)
class BalanceModel:
    """What a standing-balance controller believes, and the ankle-strategy lean's joints.

    Attributes:
        mass_kg: mass of the balance pendulum [kg].
        com_height_m: CoM height above the ground of the pendulum [m].
        support_polygon_m: plane → double-support extent ``(min, max)`` of the soles along
            the plane's axis (x sagittal, y frontal), world frame, standing pose [m].
        lean_joints: plane → the pivot joints ``(right, left)`` that lean the robot about its
            ankles (sagittal: ankle pitch; frontal: ankle roll); only the planes the robot
            can lean in (:attr:`planes`).
        hip_roll_joints: ``(right, left)`` hip roll joints that close the frontal lean's chain
            (the ankle lean's; empty names where the robot has none).
        push_bodies: push point (``"com"``, ``"trunk"``) → body the push acts on.
        control_period_s: period at which a lean controller is stepped [s].
        lean: how the robot leans: ``"ankle"`` (the ankle strategy, the frontal lean's
            legs and pelvis solved as a closed four-bar chain, :mod:`zmpkit.experiments.lean`)
            or ``"whole_body"`` (whole-body IK: soles fixed, CoM moved,
            :mod:`zmpkit.experiments.whole_body_lean`).
        lean_limits: velocity [rad/s] and acceleration [rad/s²] limits of the lean angle
            itself; None: the servo limits, scaled so no leaning joint exceeds them.
        target_span_m: the largest ZMP target of a balance sweep [m]; None: derived from the
            support polygon (:attr:`max_target_m`).
        missing_planes: plane → why the robot cannot lean in it (a leg without an ankle
            joint about that axis).
    """

    mass_kg: float
    com_height_m: float
    support_polygon_m: Mapping[str, tuple[float, float]]
    lean_joints: Mapping[str, tuple[str, str]]
    hip_roll_joints: tuple[str, str]
    push_bodies: Mapping[str, str]
    control_period_s: float = 0.01
    lean: str = "ankle"
    lean_limits: ServoLimits | None = None
    target_span_m: float | None = None
    missing_planes: Mapping[str, str] = field(default_factory=dict)

    @property
    def planes(self) -> tuple[str, ...]:
        """The planes the robot can lean in, sagittal first."""
        return tuple(p for p in ("sagittal", "frontal") if p in self.lean_joints)

    def require_plane(self, plane: str) -> tuple[str, str]:
        """The lean's pivot joints in ``plane``.

        Raises:
            ParameterError: naming why the robot cannot lean in it and the planes it can.
        """
        if plane not in self.lean_joints:
            why = self.missing_planes.get(plane, "it has no lean joints for it")
            raise ParameterError(
                f"the robot cannot lean in the {plane} plane: {why}; it can lean in: "
                f"{', '.join(self.planes) or 'none'}"
            )
        return self.lean_joints[plane]

    @property
    def max_target_m(self) -> float:
        """The largest ZMP target of a balance sweep, every plane it can lean in [m].

        ``target_span_m`` when given; else :data:`TARGET_SUPPORT_SHARE` of the support
        polygon's nearest edge (over those planes and both directions), rounded down to 1 mm.
        """
        if self.target_span_m is not None:
            return self.target_span_m
        edges = [self.support_polygon_m[p] for p in self.planes] or list(
            self.support_polygon_m.values()
        )
        edge = min(min(-low, high) for low, high in edges)
        return math.floor(TARGET_SUPPORT_SHARE * edge * 1000.0) / 1000.0


@dataclass(frozen=True, eq=False)
class WalkingDefaults:
    """A robot's walk: pattern defaults and the whole-body IK's model and settings.

    Attributes:
        com_height_m: CoM height of the walking pattern [m].
        control_period_s: the motion frame: one IK solution per period [s].
        foot_separation_m: nominal lateral distance between the foot centres [m].
        max_step_length_m: largest forward step [m].
        sole_size_m: sole ``(length, width)`` [m].
        ik_settings: the IK's joints, frames (sole sites, torso) and nominal posture.
        ik_mjcf: builds the rigid kinematic model's MJCF (the design, no actuators).
        series_joints: the hip, knee and ankle pitch joints of the left then the right leg,
            whose angles and torques the walk's time series and figures keep.
        speed_mps: the walk's default forward speed [m/s] (paper B's walk: 0.2).
        servo_stiffness_nm_per_rad: the proportional gain the user set on the leg servos,
            at the joint [N·m/rad], when they are P-only and soft: the walk then pre-loads
            them with the planned joint torques (:mod:`zmpkit.walking.servo_feedforward`)
            and the feedback walks with those of the ZMP shift they ask for
            (:mod:`zmpkit.walking.zmp_shift_feedforward`); None: the servos track (no
            feed-forward).
        servo_damping_nm_s_per_rad: the leg servos' velocity damping at the joint
            [N·m·s/rad] (a PWM drive's back-EMF: stall torque over no-load speed), which the
            feed-forward also inverts; 0 with no ``servo_stiffness_nm_per_rad``.
        observer_com_noise_m: σ_c of the ZMP/IP walk's observer, the error it assumes of the
            kinematic CoM estimate [m]; larger: a slower observer, gentler feedback (a robot
            whose joints lag their targets); None: the observer's default
            (:class:`~zmpkit.walking.zmp_observer.ZmpObserverParameters`).
        observer_zmp_noise_m: σ_p of that observer, the error it assumes of the measured ZMP
            [m]; None: its default.
        zmp_forward_m: where in each sole the walk plans its ZMP, ahead of the sole centre
            [m] (0: the centre, paper B's).
    """

    com_height_m: float
    control_period_s: float
    foot_separation_m: float
    max_step_length_m: float
    sole_size_m: tuple[float, float]
    ik_settings: IkSettings
    ik_mjcf: Callable[[], str]
    series_joints: tuple[str, ...] = ()
    speed_mps: float = DEFAULT_WALK_SPEED_MPS
    servo_stiffness_nm_per_rad: float | None = None
    servo_damping_nm_s_per_rad: float = 0.0
    observer_com_noise_m: float | None = None
    observer_zmp_noise_m: float | None = None
    zmp_forward_m: float = 0.0

    @property
    def leg_joints(self) -> tuple[str, ...]:
        """The legs' joints the IK reports, in order."""
        return self.ik_settings.joint_names

    @property
    def sole_sites(self) -> Mapping[str, str]:
        """Foot side → the site at the sole centre on the sole plane."""
        return self.ik_settings.sole_sites


@dataclass(frozen=True, eq=False)
class TruthSpec(Generic[TruthT]):
    """Where a robot's truth file lives and how it is read.

    Attributes:
        default_path: the shipped truth file.
        load: ``load(path or None)`` → the truth object (None: the shipped file).
        from_doc: ``from_doc(document, source)`` → the truth object of a YAML document.
        kind: the truth object's class (a value already loaded is taken as is).
    """

    default_path: Path
    load: Callable[[str | Path | None], TruthT]
    from_doc: Callable[[Mapping[str, Any], str | Path], TruthT]
    kind: type[TruthT]

    def resolve(self, truth: TruthT | str | Path | None) -> TruthT:
        """A truth object from a truth object, a truth file, or None (the shipped one)."""
        if isinstance(truth, self.kind):
            return truth
        return self.load(cast("str | Path | None", truth))


@dataclass(frozen=True, eq=False)
class FitSpec:
    """What the simulator fit may change in this robot's truth, and how it records.

    Attributes:
        catalogue: every fit parameter, by effect letter.
        quick_parameters: the parameters of a quick (2-parameter) fit.
        experiment: the kind of experiment the fit replays: ``"walk"`` or ``"step"``.
        fields: how the catalogue's numbers land in the compiled model, so that a batch
            of candidates shares one compilation (:mod:`~zmpkit.robots.field_rule`); None:
            each candidate is compiled.
    """

    catalogue: tuple[FitParameter, ...]
    quick_parameters: tuple[str, ...]
    experiment: str
    fields: FieldRule | None = None


@dataclass(frozen=True, eq=False)
class Robot(Generic[TruthT]):
    """A robot: everything zmpkit needs of it, built-in or from a user's ``robot.yaml``.

    Attributes:
        name: short name, e.g. the registry's key.
        title: the name written in reports and messages.
        summary: one line for ``zmpkit robot list``.
        source: what :func:`~zmpkit.robots.registry.get_robot` takes to give this robot again
            (the registry name, or the ``robot.yaml`` path): what a dataset records, and how
            the robot is pickled into a worker process, which resolves it once.
        describe: ``describe(effects, truth, contact_force_threshold_n)`` → the simulator's
            robot description (:meth:`description` passes the robot's threshold: the
            description carries a copy, this robot states it).
        driven_joints: the joints with a servo, in the robot's order.
        feet_mounts: the foot F-T sensor mounts in the world frame at the standing pose
            (the ``FEET.yaml`` layout).
        truth: the truth file and its loaders.
        servo_limits: the servos' setpoint trajectory limits.
        contact_force_threshold_n: a foot touches the floor while its vertical force is at
            least this [N] (the ZMP's contact rule).
        balance: the standing-balance model, or None if the robot has none.
        walking: the walking defaults, or None if the robot does not walk.
        fit: the simulator fit's catalogue, or None if the robot has none.
    """

    name: str
    title: str
    summary: str
    source: str
    describe: Callable[[EffectSet | str, TruthT | str | Path | None, float], RobotDescription]
    driven_joints: tuple[str, ...]
    feet_mounts: Callable[[], dict[str, FootMountEntry]]
    truth: TruthSpec[TruthT]
    servo_limits: ServoLimits
    contact_force_threshold_n: float
    balance: BalanceModel | None = None
    walking: WalkingDefaults | None = None
    fit: FitSpec | None = None

    def description(
        self, effects: EffectSet | str = "all", truth: TruthT | str | Path | None = None
    ) -> RobotDescription:
        """The simulator's description with ``effects`` on and ``truth`` (None: shipped)."""
        return self.describe(effects, truth, self.contact_force_threshold_n)

    def simulated_effects_note(
        self, effects: EffectSet | str, truth: TruthT | str | Path | None = None
    ) -> str:
        """What a report says of ``effects`` when the robot simulates fewer [text].

        Empty when the robot simulates what was asked; else e.g. ``" (simulated: S; the
        robot has no truth values for M, I, G, F)"``: a robot file without a truth has no
        motor, gear or link values, and ``all`` then runs its sensor errors only.
        """
        asked = EffectSet.parse(effects)
        simulated = self.description(effects, truth).effects
        if simulated == asked:
            return ""
        flags = ("motor", "inductance", "gear", "flex", "sensors")
        dropped = [
            letter
            for letter, name in zip("MIGFS", flags, strict=True)
            if getattr(asked, name) and not getattr(simulated, name)
        ]
        return (
            f" (simulated: {simulated.letters}; the robot has no truth values for "
            f"{', '.join(dropped)})"
        )

    def make_simulation(
        self,
        effects: EffectSet | str = "all",
        truth: TruthT | str | Path | None = None,
        seed: int = 0,
    ) -> Simulation:
        """Start a simulation of the robot standing in its initial pose.

        Args:
            effects: which effects are on (see :class:`~zmpkit.sim.effect_set.EffectSet`).
            truth: truth parameters, a truth file, or ``None`` for the shipped truth.
            seed: seed of the sensor noise.
        """
        return Simulation(self.description(effects, truth), seed=seed)

    def require_balance(self) -> BalanceModel:
        """The balance model.

        Raises:
            ParameterError: if the robot has none.
        """
        if self.balance is None:
            raise ParameterError(
                f"robot {self.name!r} has no balance model (mass, CoM height, lean joints)"
            )
        return self.balance

    def require_walking(self) -> WalkingDefaults:
        """The walking defaults.

        Raises:
            ParameterError: if the robot does not walk.
        """
        if self.walking is None:
            raise ParameterError(f"robot {self.name!r} has no walking defaults (it cannot walk)")
        return self.walking

    def require_fit(self) -> FitSpec:
        """The fit catalogue.

        Raises:
            ParameterError: if the robot has none.
        """
        if self.fit is None:
            raise ParameterError(f"robot {self.name!r} has no simulator-fit catalogue")
        return self.fit

    def ik_model(self) -> mujoco.MjModel:
        """The compiled rigid kinematic model the walking IK uses."""
        return mujoco.MjModel.from_xml_string(self.require_walking().ik_mjcf())

    @property
    def ik_settings(self) -> IkSettings:
        """The walking IK's joints, frames and nominal posture."""
        return self.require_walking().ik_settings
