r"""The robot's pose from its sensors alone: encoders, IMU orientation and the F-T contact.

A log of a controller zmpkit does not have gives no base position, so both the recorded
ZMP and the simulated one (and the feet's vertical forces) are computed by this one
function of the sensors (:meth:`LogKinematics.readings`), on the robot's model with every
unmeasured joint (gear deflection, link flex) at zero, relative to the feet:

1. the driven joints at the encoder angles, the base at the origin with the identity
   orientation: forward kinematics gives the IMU site's rotation :math:`R^0_{imu}` and
   every site's position :math:`p^0` and rotation :math:`R^0` in the base frame;
2. the base orientation that puts the IMU where it reads, heading removed (the floor
   frame's x axis is the IMU's heading):
   :math:`R_b = R_z(-\psi_{imu})\, R_{imu}\, (R^0_{imu})^\top`;
3. the floor frame's origin :math:`o_f`: horizontally the midpoint of the two sole
   centres :math:`R_b\, p^0_{sole}`, vertically the loaded sole's (the foot with the larger
   sensor :math:`F_z`), so that sole lies on z = 0;
4. the ZMP of :func:`~zmpkit.sensors.zmp.zmp_in_world` with the sensor origins
   :math:`R_b\, p^0_{ft} - o_f` and rotations :math:`R_b R^0_{ft}`: the ZMP between the feet
   [m]. Relative to the feet, not to the base: a replay's base that drifts from a start
   velocity error moves the ZMP relative to the base by the drift, but not where the
   pressure lies under the feet (measured on the built-in walker's log: the ZMP term of the true
   parameters' cost fell from 0.021 to 0.0065).

:meth:`LogKinematics.place_base` uses the same steps to start a simulation from a measured
state (:mod:`~zmpkit.simfit.shooting`).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from numpy.typing import NDArray

from zmpkit.sensors.imu import quaternion_yaw
from zmpkit.sensors.mount import wrench_in_world
from zmpkit.sensors.zmp import zmp_in_world
from zmpkit.sim.description import RobotDescription
from zmpkit.sim.names import sole_site

__all__ = ["FEET", "LogKinematics"]

FEET = ("right", "left")
"""The feet of a walk log, in its column order."""


def _rotation(quat_wxyz: NDArray[np.float64]) -> NDArray[np.float64]:
    out = np.empty(9)
    mujoco.mju_quat2Mat(out, np.asarray(quat_wxyz, dtype=np.float64))
    return out.reshape(3, 3)


def _yaw_removed(quat_wxyz: NDArray[np.float64]) -> NDArray[np.float64]:
    r""":math:`R_z(-\psi) R(q)` of an orientation ``q`` (its heading turned to x)."""
    psi = quaternion_yaw(quat_wxyz)
    c, s = math.cos(psi), math.sin(psi)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]) @ _rotation(quat_wxyz)


class LogKinematics:
    """Forward kinematics of ``model`` from encoder angles and IMU orientations.

    Args:
        model: the robot's compiled model (any candidate's: the fitted parameters do not
            move a joint axis or a site).
        description: its description (joint, IMU and F-T sensor names).
    """

    def __init__(self, model: mujoco.MjModel, description: RobotDescription) -> None:
        self.model = model
        self.data = mujoco.MjData(model)
        self.joint_names = description.driven_joints
        self._qadr = [int(model.joint(j).qposadr[0]) for j in self.joint_names]
        imu = model.sensor(description.imu.orientation)
        self._imu_site = int(imu.objid[0])
        sensors = {f.foot: f for f in description.feet}
        self._ft_site = [model.site(sensors[f].site).id for f in FEET]
        self._sole_site = [model.site(sole_site(f)).id for f in FEET]
        self.contact_threshold_n = description.contact_force_threshold_n

    def _base_frame(self, q_enc: NDArray[np.float64]) -> None:
        """Forward kinematics at the encoder angles, base at the origin, unrotated."""
        qpos = self.data.qpos
        qpos[:] = 0.0
        qpos[3] = 1.0
        qpos[self._qadr] = q_enc
        mujoco.mj_kinematics(self.model, self.data)

    def base_rotation(self, q_enc: NDArray[np.float64], quat_wxyz: NDArray[np.float64]) -> NDArray:
        r"""The base's rotation :math:`R_{imu} (R^0_{imu})^\top` (world, heading kept) [-]."""
        self._base_frame(q_enc)
        imu0 = self.data.site_xmat[self._imu_site].reshape(3, 3)
        return np.asarray(_rotation(quat_wxyz) @ imu0.T)

    def readings(
        self,
        q_enc: NDArray[np.float64],
        quat_wxyz: NDArray[np.float64],
        wrenches: NDArray[np.float64],
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The ZMP relative to the feet's midpoint (module docstring) and the feet's forces.

        Args:
            q_enc: encoder angles of the driven joints [rad], shape (J,).
            quat_wxyz: IMU orientation (w, x, y, z) [-].
            wrenches: the right and left sensor-frame wrenches [N, N·m], shape (2, 6).

        Returns:
            The ZMP (x, y) [m], NaN without a foot in contact, and the right and left
            feet's vertical forces in the floor frame [N], each shape (2,).
        """
        self._base_frame(q_enc)
        data = self.data
        imu0 = data.site_xmat[self._imu_site].reshape(3, 3)
        rb = _yaw_removed(quat_wxyz) @ imu0.T
        stance = int(np.argmax(wrenches[:, 2]))
        soles = data.site_xpos[self._sole_site] @ rb.T
        origin = data.site_xpos[self._ft_site] @ rb.T
        origin -= [*soles.mean(axis=0)[:2], soles[stance, 2]]
        xmat = np.einsum("ij,fjk->fik", rb, data.site_xmat[self._ft_site].reshape(2, 3, 3))
        force, moment = wrench_in_world(xmat.reshape(2, 9), wrenches)
        zmp = zmp_in_world(force[None], moment[None], origin[None], self.contact_threshold_n)[0]
        return zmp, force[:, 2]

    def place_base(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        quat_wxyz: NDArray[np.float64],
        omega_imu_rps: NDArray[np.float64],
        stance: int,
    ) -> None:
        r"""Put ``data``'s base where the sensors say, its stance sole at rest on the floor.

        ``data.qpos`` must hold the driven joints' angles and ``data.qvel`` their speeds
        (every other joint as it should start); the free joint is overwritten:

        - orientation :math:`R_b = R_{imu} (R^0_{imu})^\top` (heading kept);
        - angular velocity :math:`R_b^\top R_{imu}\,\omega_{imu}` (MuJoCo's free joint
          takes it in the base frame);
        - position: x, y at the origin, z so the stance sole's centre lies on z = 0;
        - linear velocity :math:`-J_{sole}\,\dot q` with the base's own linear speed at
          zero: the stance sole's centre at rest.

        Args:
            model: the simulation's model (this one's kinematics).
            data: its data.
            quat_wxyz: IMU orientation (w, x, y, z) [-].
            omega_imu_rps: IMU angular velocity in the IMU frame [rad/s].
            stance: the stance foot, an index of :data:`FEET`.
        """
        q = np.asarray([data.qpos[a] for a in self._qadr])
        rb = self.base_rotation(q, quat_wxyz)
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, rb.reshape(9))
        data.qpos[:3] = 0.0
        data.qpos[3:7] = quat
        data.qvel[:3] = 0.0
        data.qvel[3:6] = rb.T @ (_rotation(quat_wxyz) @ omega_imu_rps)
        mujoco.mj_kinematics(model, data)
        site = self._sole_site[stance]
        data.qpos[2] = -float(data.site_xpos[site][2])
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        jac = np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, jac, None, site)
        data.qvel[:3] = -(jac @ data.qvel)
