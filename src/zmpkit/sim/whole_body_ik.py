"""Whole-body differential inverse kinematics on a MuJoCo model: the one place zmpkit sets up mink.

Every user of IK stands a robot on its soles and moves its centre of mass (CoM): the walk
(:mod:`zmpkit.walking.ik`: feet and CoM on the plan, sample after sample), the walking crouch
of a user's robot (:mod:`zmpkit.robots.user_walking`: soles held, CoM lowered) and the
whole-body lean (:mod:`zmpkit.experiments.whole_body_lean`: soles held, CoM on a pendulum's
arc). :class:`WholeBodyIk` owns what they share, as mink's ``Configuration`` is the one object
every task reads:

- the configuration (the model and its joint positions ``q``),
- the tasks, in the order the QP sums them (the order fixes the floating-point result):
  one frame task per sole site (position and orientation), the torso body's orientation
  (optional), the whole-body CoM, a pull to a posture, the model's joint equalities
  (optional, and only where the model has some),
- the model's joint limits,
- the solve loop: a QP step integrated over ``dt`` until the watched errors fall below a
  tolerance or the iterations are spent (:class:`IkStop`).

Each caller keeps its own targets: it aims the public tasks (:attr:`WholeBodyIk.feet`,
:attr:`~WholeBodyIk.torso`, :attr:`~WholeBodyIk.com`) with mink's ``set_target`` (a pose from
:func:`yaw_pose`, a CoM position [m]), or holds the frames where they stand
(:meth:`WholeBodyIk.hold_frames`).

Why in ``sim/``: the solver needs a MuJoCo model and the names of its frames, never a robot;
``sim/`` is the lowest layer that speaks MuJoCo, below ``robots/`` (the crouch), ``walking/``
(the walk) and ``experiments/`` (the lean), which all import it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mink
import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ModelError, ParameterError

__all__ = ["IkCosts", "IkErrors", "IkStop", "WholeBodyIk", "yaw_pose"]


@dataclass(frozen=True)
class IkCosts:
    """Weights of the whole-body IK's tasks.

    Attributes:
        foot: weight of each sole's position [1/m] and orientation [1/rad] errors.
        com: weight of the CoM position error [1/m].
        posture: weight of the pull to the posture [1/rad].
        torso: weight of the torso orientation error [1/rad]; None: no torso task.
        equality: weight of the joint-equality residuals [-]; None: no equality task (a
            model without equalities gets none either way).
    """

    foot: float
    com: float
    posture: float
    torso: float | None = None
    equality: float | None = None

    def __post_init__(self) -> None:
        for name in ("foot", "com", "posture", "torso", "equality"):
            value = getattr(self, name)
            if value is not None:
                _validate.positive(f"IkCosts.{name}", value)


@dataclass(frozen=True)
class IkStop:
    """When one solve of :meth:`WholeBodyIk.solve` stops.

    Attributes:
        tolerance_m: stop once the watched errors are all below this [m].
        max_iterations: the most QP steps of one solve.
        watch_feet: whether the soles' position errors are watched besides the CoM's (a walk
            moves its feet; a crouch or a lean holds them where they start, and watches the
            CoM alone).
    """

    tolerance_m: float
    max_iterations: int
    watch_feet: bool = False

    def __post_init__(self) -> None:
        _validate.positive("IkStop.tolerance_m", self.tolerance_m)
        if self.max_iterations < 1:
            raise ParameterError(f"IkStop.max_iterations must be >= 1, got {self.max_iterations}")


@dataclass(frozen=True)
class IkErrors:
    """The errors a solve left.

    Attributes:
        com_m: norm of the CoM position error [m].
        foot_m: the largest sole position error [m].
        torso_rad: norm of the torso orientation error [rad]; NaN without a torso task.
    """

    com_m: float
    foot_m: float
    torso_rad: float


def yaw_pose(x: float, y: float, z: float, yaw: float, pitch: float = 0.0) -> mink.SE3:
    r"""A frame target at ``(x, y, z)`` [m] turned by ``yaw`` [rad] about z, then pitched.

    ``pitch`` [rad] turns it about its own y axis (positive: its x axis tips down, a forward
    lean): :math:`R = R_z(\psi) R_y(\theta)`.
    """
    rotation = mink.SO3.from_rpy_radians(0.0, pitch, yaw)
    return mink.SE3.from_rotation_and_translation(rotation, np.array([x, y, z]))


class WholeBodyIk:
    """Soles, torso, CoM and posture tasks on one mink configuration (module docstring).

    Args:
        model: the robot's kinematic model, floating base first.
        q: the configuration to start from, shape (nq,); the posture task pulls to it.
        sole_sites: foot side → the site at that sole's centre.
        costs: the tasks' weights (which also say whether there is a torso or equality task).
        torso_body: the body whose orientation the torso task holds; required with
            ``costs.torso``.
        solver: the QP solver mink calls.
        damping: Levenberg–Marquardt damping of the QP [-].
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        q: NDArray[np.float64],
        sole_sites: Mapping[str, str],
        costs: IkCosts,
        torso_body: str | None = None,
        solver: str = "daqp",
        damping: float = 1e-6,
    ) -> None:
        if (costs.torso is None) != (torso_body is None):
            raise ModelError("a torso task needs both IkCosts.torso and a torso_body")
        self.solver = solver
        self.damping = damping
        self.configuration = mink.Configuration(model, q)
        self.feet = {
            side: mink.FrameTask(site, "site", costs.foot, costs.foot)
            for side, site in sole_sites.items()
        }
        self.torso = (
            None
            if costs.torso is None or torso_body is None
            else mink.FrameTask(torso_body, "body", 0.0, costs.torso)  # orientation only
        )
        self.com = mink.ComTask(costs.com)
        self.posture = mink.PostureTask(model, costs.posture)
        self.posture.set_target(self.configuration.q.copy())
        tasks: list[mink.Task] = [*self.feet.values()]
        tasks += [self.torso] if self.torso is not None else []
        tasks += [self.com, self.posture]
        if costs.equality is not None and model.neq > 0:
            tasks.append(mink.EqualityConstraintTask(model, costs.equality))
        self.tasks = tasks
        self.limits = [mink.ConfigurationLimit(model)]

    def restart(self, q: NDArray[np.float64]) -> None:
        """Start again from ``q``, shape (nq,), and pull the posture to it."""
        self.configuration.update(q)
        self.posture.set_target(self.configuration.q.copy())

    def hold_frames(self) -> None:
        """Aim the sole (and torso) tasks at where those frames are now."""
        c = self.configuration
        for task in self.feet.values():
            task.set_target(c.get_transform_frame_to_world(task.frame_name, "site"))
        if self.torso is not None:
            self.torso.set_target(c.get_transform_frame_to_world(self.torso.frame_name, "body"))

    def com_error_m(self) -> float:
        """Norm of the CoM position error [m]."""
        return float(np.linalg.norm(self.com.compute_error(self.configuration)))

    def foot_error_m(self) -> float:
        """The largest sole position error [m]."""
        c = self.configuration
        return max(float(np.linalg.norm(t.compute_error(c)[:3])) for t in self.feet.values())

    def torso_error_rad(self) -> float:
        """Norm of the torso orientation error [rad]; NaN without a torso task."""
        if self.torso is None:
            return math.nan
        return float(np.linalg.norm(self.torso.compute_error(self.configuration)[3:]))

    def errors(self) -> IkErrors:
        """The CoM, largest sole position and torso orientation errors now."""
        return IkErrors(self.com_error_m(), self.foot_error_m(), self.torso_error_rad())

    def solve(self, dt_s: float, stop: IkStop) -> IkErrors:
        """Integrate QP steps of ``dt_s`` [s] until ``stop`` says so; the errors left.

        The solve ends at the first step after which the watched errors (the CoM's, and the
        soles' if ``stop.watch_feet``) are all below the tolerance, or after
        ``stop.max_iterations`` steps.
        """
        for _ in range(stop.max_iterations):
            velocity = mink.solve_ik(
                self.configuration, self.tasks, dt_s, self.solver, self.damping,
                limits=self.limits,
            )  # fmt: skip
            self.configuration.integrate_inplace(velocity, dt_s)
            if self._converged(stop):
                break
        return self.errors()

    def _converged(self, stop: IkStop) -> bool:
        if self.com_error_m() >= stop.tolerance_m:
            return False
        return not stop.watch_feet or self.foot_error_m() < stop.tolerance_m
