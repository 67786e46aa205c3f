r"""Foot damping control: the stance ankles move the measured ZMP to the one a stabiliser asks for.

The CoP-tracking layer of today's position-controlled walkers (Kajita et al., "Biped walking
stabilization based on linear inverted pendulum tracking", IROS 2010; Caron et al.,
lipm_walking_controller, ICRA 2019): a stabiliser asks for a ZMP ``p^d``; each foot in contact
turns its ankle at a rate proportional to the ankle torque still missing, and the servo's
stiffness turns the angle into torque. With a foot's vertical force ``F_z`` [N] and the ZMP
error ``e = p^d - p`` in the foot's frame (its yaw), the missing torque is ``F_z e`` (moving
the whole ZMP by ``e`` asks each foot's CoP to move by ``e``, since the ZMP is their
``F_z``-weighted mean), so per foot

.. math::

    \dot θ_y = A_x\,F_z\,e_x - θ_y / T, \qquad \dot θ_x = -A_y\,F_z\,e_y - θ_x / T

(``θ_y`` about the sole's lateral axis, toe down positive: presses the toe, moves the CoP
forward; ``θ_x`` about its forward axis: a positive roll lifts the left edge, so a ZMP wanted
to the left needs a negative one). ``A_x, A_y`` [rad/(N·m·s)] are the admittances of the
sagittal and the lateral CoP, ``T`` [s] the leak
that returns the ankle to the plan when nothing is asked (a foot without contact leaks with
``T_swing``, so that it lands as planned), and ``|θ| ≤ θ_max`` bounds what the loop may do
to the gait. The angles are added to the joint targets of the ankle's pitch and roll joints,
signed by each joint's axis in the sole frame (:func:`ankle_joints`). Every gain and limit is
declared and checked (:class:`FootDampingParameters`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit import _validate
from zmpkit.errors import ModelError, ParameterError

__all__ = ["AnkleJoints", "FootDamping", "FootDampingParameters", "ankle_joints"]


@dataclass(frozen=True)
class FootDampingParameters:
    """Gains and limits of foot damping control (module docstring).

    Attributes:
        admittance_rad_per_n_m_s: (A_x, A_y), ankle rate per missing torque for the CoP's
            forward and lateral error [rad/(N·m·s)]; 0: that axis off.
        leak_time_constant_s: T, return to the plan in contact [s].
        swing_time_constant_s: T_swing, return to the plan without contact [s].
        max_angle_rad: θ_max, the largest ankle correction [rad].
    """

    admittance_rad_per_n_m_s: tuple[float, float] = (0.0, 0.0)
    leak_time_constant_s: float = 0.5
    swing_time_constant_s: float = 0.05
    max_angle_rad: float = 0.05

    def __post_init__(self) -> None:
        if len(self.admittance_rad_per_n_m_s) != 2:
            raise ParameterError(
                f"FootDampingParameters.admittance_rad_per_n_m_s must be (A_x, A_y); got "
                f"{self.admittance_rad_per_n_m_s}"
            )
        for value in self.admittance_rad_per_n_m_s:
            _validate.non_negative("FootDampingParameters.admittance_rad_per_n_m_s", value)
        for name in ("leak_time_constant_s", "swing_time_constant_s", "max_angle_rad"):
            _validate.positive(f"FootDampingParameters.{name}", getattr(self, name))
        if self.max_angle_rad > 0.2:
            raise ParameterError(
                f"FootDampingParameters.max_angle_rad must be <= 0.2 rad (a correction, not a "
                f"gait); got {self.max_angle_rad}"
            )


@dataclass(frozen=True)
class AnkleJoints:
    """One foot's ankle joints and their signs in its sole frame.

    Attributes:
        pitch_joint: the joint whose axis is closest to the sole's lateral axis.
        roll_joint: the joint whose axis is closest to the sole's forward axis.
        pitch_sign: +1 if the pitch joint's axis points along the sole's +y, else -1 [-].
        roll_sign: +1 if the roll joint's axis points along the sole's +x, else -1 [-].
    """

    pitch_joint: str
    roll_joint: str
    pitch_sign: float
    roll_sign: float


def ankle_joints(model: mujoco.MjModel, sole_site: str) -> AnkleJoints:
    """The two hinge joints nearest the sole, told apart by their axes in the sole frame.

    Walks from the sole site's body towards the root and takes the first two hinges (a
    humanoid's ankle roll and pitch); each joint's axis is expressed in the sole frame at the
    model's reference pose.

    Raises:
        ModelError: no such site, or fewer than two hinges below the root, or two hinges
            whose axes do not tell pitch from roll.
    """
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, sole_site)
    if site < 0:
        raise ModelError(f"no site {sole_site!r} in the model")
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    sole_rotation = data.site_xmat[site].reshape(3, 3)
    hinges: list[int] = []
    body = int(model.site_bodyid[site])
    while body > 0 and len(hinges) < 2:
        start, count = int(model.body_jntadr[body]), int(model.body_jntnum[body])
        for joint in range(start + count - 1, start - 1, -1):
            if model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_HINGE and len(hinges) < 2:
                hinges.append(joint)
        body = int(model.body_parentid[body])
    if len(hinges) < 2:
        raise ModelError(f"fewer than two hinge joints above the sole {sole_site!r}")
    axes = []
    for joint in hinges:
        body_rotation = data.xmat[model.jnt_bodyid[joint]].reshape(3, 3)
        axis_in_world = body_rotation @ model.jnt_axis[joint]
        axes.append(sole_rotation.T @ axis_in_world)
    lateral = [abs(float(a[1])) for a in axes]
    pitch = int(np.argmax(lateral))
    roll = 1 - pitch
    if lateral[pitch] < 0.7 or abs(float(axes[roll][0])) < 0.7:
        raise ModelError(
            f"the two joints above the sole {sole_site!r} are not an ankle pitch and roll "
            f"(axes in the sole frame {[np.round(a, 2).tolist() for a in axes]})"
        )
    name = lambda j: str(mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j))  # noqa: E731
    return AnkleJoints(
        pitch_joint=name(hinges[pitch]),
        roll_joint=name(hinges[roll]),
        pitch_sign=math.copysign(1.0, float(axes[pitch][1])),
        roll_sign=math.copysign(1.0, float(axes[roll][0])),
    )


class FootDamping:
    """Foot damping control of a robot's feet (module docstring).

    Args:
        parameters: gains and limits.
        ankles: foot -> its ankle joints, in the order the feet are given to :meth:`update`.
        joint_names: the joint targets' order.
        period_s: the control period [s].
    """

    def __init__(
        self,
        parameters: FootDampingParameters,
        ankles: Mapping[str, AnkleJoints],
        joint_names: tuple[str, ...],
        period_s: float,
    ) -> None:
        self.parameters = parameters
        self.period_s = _validate.positive("period_s", period_s, "s")
        self.feet = tuple(ankles)
        missing = [
            j
            for a in ankles.values()
            for j in (a.pitch_joint, a.roll_joint)
            if j not in joint_names
        ]
        if missing:
            raise ModelError(f"ankle joints {missing} are not among the targets {joint_names}")
        self._index = [
            (joint_names.index(a.pitch_joint), joint_names.index(a.roll_joint))
            for a in ankles.values()
        ]
        self._sign = [(a.pitch_sign, a.roll_sign) for a in ankles.values()]
        self.angle_rad = np.zeros((len(self.feet), 2))
        """Each foot's correction (θ_y, θ_x) in its sole frame [rad], shape (F, 2)."""

    def update(
        self,
        zmp_error_in_world: NDArray[np.float64],
        force_z_n: NDArray[np.float64],
        foot_yaw_rad: NDArray[np.float64],
        contact_threshold_n: float,
    ) -> None:
        """One control period of the law.

        Args:
            zmp_error_in_world: ``p^d - p`` (x, y) [m]; NaN (no ZMP) only leaks.
            force_z_n: each foot's vertical force [N], shape (F,).
            foot_yaw_rad: each foot's heading [rad], shape (F,).
            contact_threshold_n: ``F_z`` from which a foot is in contact [N].
        """
        par, dt = self.parameters, self.period_s
        (gain_x, gain_y), limit = par.admittance_rad_per_n_m_s, par.max_angle_rad
        ex, ey = float(zmp_error_in_world[0]), float(zmp_error_in_world[1])
        valid = math.isfinite(ex) and math.isfinite(ey)
        for i in range(len(self.feet)):
            fz = float(force_z_n[i])
            angle = self.angle_rad[i]
            if fz >= contact_threshold_n:
                rate_y = rate_x = 0.0
                if valid:
                    c, s = math.cos(float(foot_yaw_rad[i])), math.sin(float(foot_yaw_rad[i]))
                    local_x, local_y = c * ex + s * ey, -s * ex + c * ey
                    rate_y, rate_x = gain_x * fz * local_x, -gain_y * fz * local_y
                leak = par.leak_time_constant_s
            else:
                rate_y = rate_x = 0.0
                leak = par.swing_time_constant_s
            for axis, rate in ((0, rate_y), (1, rate_x)):
                value = float(angle[axis]) + dt * (rate - float(angle[axis]) / leak)
                angle[axis] = min(max(value, -limit), limit)

    def apply(self, q_target_rad: NDArray[np.float64]) -> None:
        """Add the corrections to the ankle joints of ``q_target_rad`` [rad], in place."""
        for (pitch, roll), (s_pitch, s_roll), angle in zip(
            self._index, self._sign, self.angle_rad, strict=True
        ):
            q_target_rad[pitch] += s_pitch * float(angle[0])
            q_target_rad[roll] += s_roll * float(angle[1])
