"""What the multibody ZMP adds to the cart table's on a planned motion (closed forms)."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from zmpkit.walking.ik import JointTrajectory
from zmpkit.walking.multibody_zmp import expected_zmp_offset

G = 9.81
Z_C = 0.3  # [m]

POINT_MASS = """<mujoco><option gravity="0 0 -9.81"/><worldbody>
  <body name="cart"><freejoint/><geom type="sphere" size="0.01" mass="2"/></body>
</worldbody></mujoco>"""

SPINNING = """<mujoco><option gravity="0 0 -9.81"/><worldbody>
  <body name="cart"><freejoint/>
    <inertial pos="0 0 0" mass="2" diaginertia="0.02 0.04 0.03"/>
  </body>
</worldbody></mujoco>"""


def _central(omega: float, dt: float) -> float:
    """What a central second difference makes of a sinusoid's second derivative [-]."""
    return 2.0 * (1.0 - math.cos(omega * dt)) / (omega * dt) ** 2


def _trajectory(x: np.ndarray, pitch: np.ndarray, dt: float) -> JointTrajectory:
    n = x.size
    base = np.zeros((n, 7))
    base[:, 0], base[:, 2] = x, Z_C
    base[:, 3], base[:, 5] = np.cos(pitch / 2), np.sin(pitch / 2)  # about y
    zero = np.zeros(n)
    return JointTrajectory(
        time_s=np.arange(n) * dt,
        joint_names=(),
        q_rad=np.zeros((n, 0)),
        base_qpos=base,
        com_error_m=zero,
        foot_error_m=zero,
        torso_error_rad=zero,
    )


def test_a_point_mass_is_its_own_cart_table() -> None:
    """A lone point mass at the cart table's height has the cart table's ZMP: nothing to add."""
    dt, omega, amplitude = 0.005, 2 * math.pi * 2.0, 0.03
    t = np.arange(400) * dt
    x = amplitude * np.sin(omega * t)
    cart_table = np.column_stack([x + Z_C / G * amplitude * omega**2 * np.sin(omega * t), 0 * t])
    model = mujoco.MjModel.from_xml_string(POINT_MASS)
    offset = expected_zmp_offset(model, _trajectory(x, 0 * t, dt), cart_table)
    inner = slice(1, -1)  # the ends are taken at rest
    # Central differences see a sinusoid's acceleration scaled by 2(1 − cos ω dt)/(ω dt)²
    # (1 − 3e-4 here): the only difference left, exactly.
    acceleration = -amplitude * omega**2 * np.sin(omega * t)
    seen = acceleration * _central(omega, dt)
    np.testing.assert_allclose(
        offset[inner, 0], (-Z_C / G * (seen - acceleration))[inner], atol=1e-9
    )
    np.testing.assert_allclose(offset[inner, 1], 0.0, atol=1e-12)


def test_a_spinning_body_adds_its_angular_momentum_rate() -> None:
    """A body pitching in place: the cart table (its CoM at rest) puts the ZMP under it; the
    ground must also supply I θ̈, which moves the ZMP by −I_yy θ̈ / (m g) along x."""
    dt, omega, amplitude = 0.005, 2 * math.pi * 1.0, 0.2
    t = np.arange(400) * dt
    pitch = amplitude * np.sin(omega * t)
    model = mujoco.MjModel.from_xml_string(SPINNING)
    offset = expected_zmp_offset(model, _trajectory(0 * t, pitch, dt), np.zeros((t.size, 2)))
    pitch_acc = -amplitude * omega**2 * np.sin(omega * t) * _central(omega, dt)
    expected_x = -0.04 * pitch_acc / (2.0 * G)
    inner = slice(1, -1)
    np.testing.assert_allclose(offset[inner, 0], expected_x[inner], atol=1e-9)
    np.testing.assert_allclose(offset[inner, 1], 0.0, atol=1e-12)
